// The RGL tensor_file container (brdf/tensor_file.h): ReadTensorFile, and AsFloat32 of every
// field read.
#include <cstddef>
#include <cstdint>

#include "brdf/tensor_file.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = zbrdf::fuzz::WriteScratchFile("tensor.bsdf", data, size);
  zbrdf::fuzz::ExpectOnlyInputErrors([&] {
    for (const auto& entry : zbrdf::ReadTensorFile(path)) {
      zbrdf::fuzz::ExpectOnlyInputErrors([&] { (void)entry.second.AsFloat32(entry.first); });
    }
  });
  return 0;
}
