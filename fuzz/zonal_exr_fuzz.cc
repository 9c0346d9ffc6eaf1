// zonal.exr (acquisition/zonal.h): ReadZonalExr.
#include <cstddef>
#include <cstdint>

#include "acquisition/zonal.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = zbrdf::fuzz::WriteScratchFile("zonal.exr", data, size);
  zbrdf::fuzz::ExpectOnlyInputErrors([&] { (void)zbrdf::ReadZonalExr(path); });
  return 0;
}
