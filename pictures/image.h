// Linear RGB images for previews and environment maps: OpenEXR in and out, and the tone-mapped
// 8-bit PNGs people look at.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "basis/vec3.h"

namespace zbrdf {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<Rgb> pixels;  // row-major, top row first

  RgbImage() = default;
  RgbImage(int w, int h) : width(w), height(h), pixels(static_cast<size_t>(w) * h) {}
  Rgb& At(int x, int y) { return pixels[static_cast<size_t>(y) * width + x]; }
  const Rgb& At(int x, int y) const { return pixels[static_cast<size_t>(y) * width + x]; }
};

// Reads the R, G, B channels of an OpenEXR file (any pixel type; missing channels are 0).
// Throws InputError naming the file if it cannot be read or holds NaN or infinite values.
// Negative values are set to 0 and counted in *negative_pixels (if given).
RgbImage ReadExrImage(const std::string& path, int* negative_pixels = nullptr);
// Reads a Radiance RGBE (.hdr, "radiance" or "RGBE" header) image through OpenCV, with the same
// checks and negative-value handling as ReadExrImage.
RgbImage ReadHdrImage(const std::string& path, int* negative_pixels = nullptr);
// ReadExrImage or ReadHdrImage by the file's extension (.exr, .hdr or .pic, any case); any other
// extension is an InputError naming the formats read.
RgbImage ReadEnvironmentImage(const std::string& path, int* negative_pixels = nullptr);
// Writes 32-bit float R, G, B (atomically). Throws InputError if it cannot.
void WriteExrImage(const std::string& path, const RgbImage& image);

// Tone mapping for display: scale by 2^exposure_ev, the ACES filmic curve fitted by Narkowicz
// 2015 ("ACES Filmic Tone Mapping Curve"), x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14),
// clamped to [0, 1], then the sRGB transfer function. Returns an 8-bit BGR image (OpenCV).
cv::Mat ToneMap(const RgbImage& image, double exposure_ev = 0.0);
// sRGB encoding of a linear value in [0, 1] (IEC 61966-2-1).
double SrgbEncode(double linear);

// Writes an 8-bit image as PNG (atomically). Throws InputError if it cannot.
void WritePng(const std::string& path, const cv::Mat& bgr);
// The PNG file's bytes (for embedding): EncodeBgrPng, drivers/bgr_png.h.

}  // namespace zbrdf
