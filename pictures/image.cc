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
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "drivers/bgr_png.h"

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
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  if (!in || !(buffer << in.rdbuf())) {
    throw InputError("cannot read Radiance HDR image " + path + ": the file cannot be read");
  }
  const std::string bytes = buffer.str();
  const auto fail = [&path](const std::string& why) {
    return InputError("cannot read Radiance HDR image " + path + ": " + why +
                      " (write it again as a standard .hdr, or as .exr)");
  };
  // Header (Ward, "Real pixels", Graphics Gems II, and Radiance's file formats): "#?" and the
  // program name, lines of VARIABLE=value up to an empty line, then the resolution line. Only the
  // RGBE format is read; EXPOSURE and other variables are ignored, as most readers do.
  size_t at = 0;
  const auto next_line = [&bytes, &at](std::string* line) {
    const size_t end = bytes.find('\n', at);
    if (end == std::string::npos) return false;
    *line = bytes.substr(at, end - at);
    at = end + 1;
    return true;
  };
  std::string line;
  if (!next_line(&line) || line.compare(0, 2, "#?") != 0) throw fail("it does not start with #?");
  while (true) {
    if (!next_line(&line)) throw fail("its header does not end");
    if (line.empty()) break;
    if (line.compare(0, 7, "FORMAT=") == 0 && line != "FORMAT=32-bit_rle_rgbe") {
      throw fail("its pixels are " + line.substr(7) + ", not 32-bit_rle_rgbe");
    }
  }
  int width = 0, height = 0, consumed = 0;
  if (!next_line(&line) ||
      std::sscanf(line.c_str(), "-Y %d +X %d%n", &height, &width, &consumed) != 2 ||
      consumed != static_cast<int>(line.size())) {
    throw fail("its resolution line '" + line.substr(0, 40) +
               "' is not '-Y height +X width' (the standard orientation)");
  }
  if (width <= 0 || height <= 0 || static_cast<uint64_t>(width) * height > (1ull << 28)) {
    throw fail("it declares " + std::to_string(width) + "x" + std::to_string(height) + " pixels");
  }
  // Scanlines of RGBE quadruples, each flat or, for widths of 8 to 32767, run-length encoded per
  // component: 2, 2, width (16 bits), then runs (count > 128: count - 128 copies of one byte) and
  // literals (count <= 128 bytes) of R, then G, B and E.
  const auto byte_at = [&bytes](size_t i) { return static_cast<uint8_t>(bytes[i]); };
  std::vector<uint8_t> scanline(static_cast<size_t>(width) * 4);
  RgbImage image(width, height);
  int negatives = 0;
  for (int y = 0; y < height; ++y) {
    const bool rle = width >= 8 && width <= 0x7fff && at + 4 <= bytes.size() && byte_at(at) == 2 &&
                     byte_at(at + 1) == 2 && (byte_at(at + 2) & 0x80) == 0;
    if (rle) {
      if ((byte_at(at + 2) << 8 | byte_at(at + 3)) != width) {
        throw fail("scanline " + std::to_string(y) + " has the wrong length");
      }
      at += 4;
      for (int c = 0; c < 4; ++c) {
        for (int x = 0; x < width;) {
          if (at >= bytes.size()) throw fail("it ends in scanline " + std::to_string(y));
          int count = byte_at(at++);
          const bool run = count > 128;
          if (run) count -= 128;
          if (count == 0 || count > width - x || at + (run ? 1 : count) > bytes.size()) {
            throw fail("scanline " + std::to_string(y) + " is damaged");
          }
          for (int k = 0; k < count; ++k) {
            scanline[static_cast<size_t>(x + k) * 4 + c] = byte_at(run ? at : at + k);
          }
          at += run ? 1 : count;
          x += count;
        }
      }
    } else {
      if (at + scanline.size() > bytes.size()) {
        throw fail("it ends in scanline " + std::to_string(y));
      }
      std::memcpy(scanline.data(), bytes.data() + at, scanline.size());
      at += scanline.size();
    }
    for (int x = 0; x < width; ++x) {
      const uint8_t* q = &scanline[static_cast<size_t>(x) * 4];
      // Mantissas times 2^(E - 128 - 8); E = 0 is black.
      const double f = q[3] == 0 ? 0.0 : std::ldexp(1.0, static_cast<int>(q[3]) - 136);
      StorePixel(path, image, static_cast<size_t>(y) * width + x, Rgb(q[0] * f, q[1] * f, q[2] * f),
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

void WritePng(const std::string& path, const cv::Mat& bgr) {
  WriteFileAtomically(path, EncodeBgrPng(bgr));
}

}  // namespace zbrdf
