// Frame files (acquisition/frame_file.h): DecodeFrameFile on a session's frames/*.tiff bytes,
// expected to be a 16 x 12 raw frame (the size of the seed corpus' frames).
#include <cstddef>
#include <cstdint>
#include <string>

#include "acquisition/frame_file.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  zbrdf::fuzz::ExpectOnlyInputErrors(
      [&] { (void)zbrdf::DecodeFrameFile(bytes, 16, 12, "frame fuzz.tiff"); });
  return 0;
}
