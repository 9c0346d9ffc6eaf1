// SH BRDF files (brdf/sh_file.h): ReadShFile.
#include <cstddef>
#include <cstdint>

#include "brdf/sh_file.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = zbrdf::fuzz::WriteScratchFile("sh.exr", data, size);
  zbrdf::fuzz::ExpectOnlyInputErrors([&] { (void)zbrdf::ReadShFile(path); });
  return 0;
}
