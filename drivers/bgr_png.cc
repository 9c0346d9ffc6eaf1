#include "drivers/bgr_png.h"

#include "basis/error.h"
#include "basis/png.h"

namespace zbrdf {

std::string EncodeBgrPng(const cv::Mat& image) {
  const int channels = image.channels();
  if (image.empty() || (image.depth() != CV_8U && image.depth() != CV_16U) ||
      (channels != 1 && channels != 3 && channels != 4)) {
    throw InputError("cannot encode a PNG image of OpenCV type " + std::to_string(image.type()) +
                     " (" + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                     "): give a non-empty 8- or 16-bit gray, BGR or BGRA image");
  }
  PngImage png(image.cols, image.rows, channels, image.depth() == CV_8U ? 8 : 16);
  // OpenCV's B, G, R(, A) to PNG's R, G, B(, A).
  const int from[4] = {channels >= 3 ? 2 : 0, 1, 0, 3};
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      for (int c = 0; c < channels; ++c) {
        const int i = x * channels + from[c];
        png.At(x, y, c) =
            image.depth() == CV_8U ? image.ptr<uint8_t>(y)[i] : image.ptr<uint16_t>(y)[i];
      }
    }
  }
  return EncodePng(png);
}

}  // namespace zbrdf
