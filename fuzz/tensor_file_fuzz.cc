// The RGL tensor_file container (tools/tensor_file.h): ReadTensorFile, and AsFloat32 of every
// field read.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_util.h"
#include "tools/tensor_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = zbrdf::fuzz::WriteScratchFile("tensor.bsdf", data, size);
  zbrdf::fuzz::ExpectOnlyInputErrors([&] {
    for (const auto& entry : zbrdf::ReadTensorFile(path)) {
      zbrdf::fuzz::ExpectOnlyInputErrors([&] { (void)entry.second.AsFloat32(entry.first); });
    }
  });
  return 0;
}
