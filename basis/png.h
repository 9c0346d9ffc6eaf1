// PNG images in memory, through libspng: the pictures zbrdf writes for people (8-bit gray, RGB,
// RGBA), the projector's patterns (8- or 16-bit gray) and the frames of earlier versions (16-bit
// gray), and reading them back.
//
// zbrdf once encoded and decoded these with OpenCV's imgcodecs, which links GDAL, GDCM and ~120
// other libraries into every process: 0.1 s of CPU to start one, and decoders that zbrdf never
// wants (GDCM's aborted on a damaged frame). docs/design.md, section 5.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace zbrdf {

// An image of 8- or 16-bit samples: width x height pixels of `channels` samples each (1 gray,
// 2 gray and alpha, 3 RGB, 4 RGBA, in that order), rows top to bottom. 8-bit samples are
// 0..255, 16-bit ones 0..65535; both are held in `samples` (width * height * channels).
struct PngImage {
  int width = 0;
  int height = 0;
  int channels = 0;
  int bit_depth = 0;  // 8 or 16
  std::vector<uint16_t> samples;

  PngImage() = default;
  PngImage(int width, int height, int channels, int bit_depth);
  uint16_t& At(int x, int y, int c = 0) {
    return samples[(static_cast<size_t>(y) * width + x) * channels + c];
  }
  uint16_t At(int x, int y, int c = 0) const {
    return samples[(static_cast<size_t>(y) * width + x) * channels + c];
  }
};

// The PNG file of `image`. compression_level: zlib's 0 (none, fastest) to 9 (smallest), -1 its
// default (6). Throws InputError for an image that is not 1-4 channels of 8 or 16 bits, of a
// sample count other than width x height x channels, or with an 8-bit sample above 255.
std::string EncodePng(const PngImage& image, int compression_level = -1);

// The image in a PNG file's bytes, as the file stores it (a gray file gives 1 channel, an RGB one
// 3, ...; no gamma or colour conversion). Palette files and gray files of under 8 bits are not
// read. Throws InputError naming `what` (the file, for the message) for anything that is not a
// whole, undamaged PNG of those kinds (checksums included), and for one whose pixels would take
// more than 2 GB.
PngImage DecodePng(std::string_view bytes, const std::string& what);

}  // namespace zbrdf
