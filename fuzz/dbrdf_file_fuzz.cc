// D-BRDF files (brdf/dbrdf_file.h): ReadDBrdfFile and ReadDBrdfFileInfo; a model read is then
// evaluated and sampled at a few directions.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "brdf/dbrdf_file.h"
#include "fuzz/brdf_probe.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = zbrdf::fuzz::WriteScratchFile("dbrdf.exr", data, size);
  zbrdf::fuzz::ExpectOnlyInputErrors([&] { (void)zbrdf::ReadDBrdfFileInfo(path); });
  zbrdf::fuzz::ExpectOnlyInputErrors(
      [&] { zbrdf::fuzz::ProbeBrdf(*zbrdf::ReadDBrdfFile(path)); });
  return 0;
}
