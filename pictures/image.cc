#include "pictures/image.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "basis/atomic_file.h"
#include "basis/error.h"

namespace zbrdf {
namespace {

// The checks every environment reader makes: NaN and infinity are errors, negative values are
// set to 0 and counted (the caller warns).
void StorePixel(const std::string& path, RgbImage& image, size_t i, Rgb v, int* negatives) {
  if (!v.IsFinite()) {
    throw InputError("environment map " + path + ": pixel " + std::to_string(i % image.width) +
                     "," + std::to_string(i / image.width) +
                     " is NaN or infinite; repair the image");
  }
  if (v.r < 0 || v.g < 0 || v.b < 0) {
    ++*negatives;
    v = Rgb(std::max(0.0, v.r), std::max(0.0, v.g), std::max(0.0, v.b));
  }
  image.pixels[i] = v;
}

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

RgbImage ReadHdrImage(const std::string& path, int* negative_pixels) {
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError("cannot read Radiance HDR image " + path + ": no such file");
  }
  cv::Mat bgr;
  try {
    bgr = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_COLOR);
  } catch (const cv::Exception& e) {
    throw InputError("cannot read Radiance HDR image " + path + ": " + e.what());
  }
  if (bgr.empty() || bgr.type() != CV_32FC3) {
    throw InputError("cannot read Radiance HDR image " + path +
                     ": not an RGBE file OpenCV can decode (write .hdr or .exr)");
  }
  RgbImage image(bgr.cols, bgr.rows);
  int negatives = 0;
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3f p = bgr.at<cv::Vec3f>(y, x);
      StorePixel(path, image, static_cast<size_t>(y) * image.width + x, Rgb(p[2], p[1], p[0]),
                 &negatives);
    }
  }
  if (negative_pixels) *negative_pixels = negatives;
  return image;
}

RgbImage ReadEnvironmentImage(const std::string& path, int* negative_pixels) {
  const std::string ext = LowerExtension(path);
  if (ext == ".exr") return ReadExrImage(path, negative_pixels);
  if (ext == ".hdr" || ext == ".pic") return ReadHdrImage(path, negative_pixels);
  throw InputError("environment map " + path +
                   ": unknown file type; give an OpenEXR (.exr) or Radiance RGBE (.hdr) "
                   "latitude-longitude image");
}

RgbImage ReadExrImage(const std::string& path, int* negative_pixels) {
  RgbImage image;
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    image = RgbImage(window.max.x - window.min.x + 1, window.max.y - window.min.y + 1);
    std::vector<float> channels[3];
    Imf::FrameBuffer fb;
    for (int c = 0; c < 3; ++c) {
      channels[c].assign(image.pixels.size(), 0.0f);
      char* base =
          reinterpret_cast<char*>(channels[c].data()) -
          (static_cast<ptrdiff_t>(window.min.y) * image.width + window.min.x) * sizeof(float);
      fb.insert(kRgbChannelNames[c], Imf::Slice(Imf::FLOAT, base, sizeof(float),
                                                sizeof(float) * image.width, 1, 1, 0.0));
    }
    file.setFrameBuffer(fb);
    file.readPixels(window.min.y, window.max.y);
    int negatives = 0;
    for (size_t i = 0; i < image.pixels.size(); ++i) {
      StorePixel(path, image, i, Rgb(channels[0][i], channels[1][i], channels[2][i]), &negatives);
    }
    if (negative_pixels) *negative_pixels = negatives;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read OpenEXR image " + path + ": " + e.what());
  }
  return image;
}

void WriteExrImage(const std::string& path, const RgbImage& image) {
  Imf::StdOSStream stream;  // encoded in memory, written through basis/atomic_file.h
  try {
    Imf::Header header(image.width, image.height);
    Imf::FrameBuffer fb;
    std::vector<float> channels[3];
    for (int c = 0; c < 3; ++c) {
      channels[c].resize(image.pixels.size());
      for (size_t i = 0; i < image.pixels.size(); ++i) {
        channels[c][i] = static_cast<float>(image.pixels[i][c]);
      }
      header.channels().insert(kRgbChannelNames[c], Imf::Channel(Imf::FLOAT));
      fb.insert(kRgbChannelNames[c],
                Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(channels[c].data()), sizeof(float),
                           sizeof(float) * image.width));
    }
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(fb);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    throw InputError("cannot encode OpenEXR image " + path + ": " + e.what());
  }
  WriteFileAtomically(path, stream.str());
}

double SrgbEncode(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

cv::Mat ToneMap(const RgbImage& image, double exposure_ev) {
  const double scale = std::exp2(exposure_ev);
  cv::Mat out(image.height, image.width, CV_8UC3);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const Rgb& v = image.At(x, y);
      cv::Vec3b& p = out.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) {
        const double l = std::max(0.0, v[c] * scale);
        const double mapped =
            std::clamp(l * (2.51 * l + 0.03) / (l * (2.43 * l + 0.59) + 0.14), 0.0, 1.0);
        p[2 - c] = static_cast<uint8_t>(std::lround(255.0 * SrgbEncode(mapped)));
      }
    }
  }
  return out;
}

std::string EncodePng(const cv::Mat& bgr) {
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", bgr, bytes)) throw InputError("cannot encode a PNG image");
  return std::string(bytes.begin(), bytes.end());
}

void WritePng(const std::string& path, const cv::Mat& bgr) {
  WriteFileAtomically(path, EncodePng(bgr));
}

}  // namespace zbrdf
