#include "acquisition/frame_file.h"

#include <cstdio>
#include <sstream>
#include <string_view>

#include <opencv2/imgcodecs.hpp>
#include <tiffio.h>
#include <tiffio.hxx>

#include "basis/error.h"

namespace zbrdf {

std::string EncodeFrameFile(const Frame& frame) {
  if (frame.layout == PixelLayout::kRgb || frame.width <= 0 || frame.height <= 0 ||
      frame.data.size() != static_cast<size_t>(frame.width) * frame.height) {
    throw DeviceError("camera delivered a " + PixelLayoutName(frame.layout) + " frame of " +
                      std::to_string(frame.data.size()) + " samples for " +
                      std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                      " pixels; zbrdf captures raw mono or Bayer frames");
  }
  std::ostringstream stream;
  TIFF* tiff = TIFFStreamOpen("frame", &stream);
  if (tiff == nullptr) throw InternalError("libtiff cannot open an in-memory stream");
  char description[160];
  std::snprintf(description, sizeof(description),
                "zbrdf raw frame: layout %s, %d significant bits, exposure %.3f us",
                PixelLayoutName(frame.layout).c_str(), frame.bit_depth, frame.exposure_us);
  const int rows_per_strip = 64;
  bool ok = TIFFSetField(tiff, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(frame.width)) &&
            TIFFSetField(tiff, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(frame.height)) &&
            TIFFSetField(tiff, TIFFTAG_BITSPERSAMPLE, 16) &&
            TIFFSetField(tiff, TIFFTAG_SAMPLESPERPIXEL, 1) &&
            TIFFSetField(tiff, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK) &&
            TIFFSetField(tiff, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG) &&
            TIFFSetField(tiff, TIFFTAG_COMPRESSION, COMPRESSION_ZSTD) &&
            TIFFSetField(tiff, TIFFTAG_ZSTD_LEVEL, 1) &&
            TIFFSetField(tiff, TIFFTAG_ROWSPERSTRIP, rows_per_strip) &&
            TIFFSetField(tiff, TIFFTAG_IMAGEDESCRIPTION, description) &&
            TIFFSetField(tiff, TIFFTAG_SOFTWARE, "zbrdf");
  // Whole strips from the frame's buffer (libtiff copies before compressing; the predictor,
  // which would modify the buffer in place, stays off: it does not help a Bayer mosaic).
  const size_t row_bytes = static_cast<size_t>(frame.width) * sizeof(uint16_t);
  for (int y = 0; ok && y < frame.height; y += rows_per_strip) {
    const int rows = std::min(rows_per_strip, frame.height - y);
    ok = TIFFWriteEncodedStrip(tiff, y / rows_per_strip,
                               const_cast<uint16_t*>(frame.data.data()) +
                                   static_cast<size_t>(y) * frame.width,
                               static_cast<tmsize_t>(rows * row_bytes)) >= 0;
  }
  TIFFClose(tiff);
  if (!ok) throw InternalError("libtiff failed to encode a frame (is libtiff built with zstd?)");
  return stream.str();
}

namespace {

// Whether a TIFF's first directory describes the expected frame: width x height, one 16-bit
// sample per pixel, in strips. Checked with libtiff before any pixel buffer is allocated: a few
// damaged header bytes can otherwise declare gigabytes (found by fuzz/frame_file_fuzz).
bool TiffDescribesFrame(const std::string& bytes, int width, int height) {
  std::istringstream in(bytes);
  TIFF* tiff = TIFFStreamOpen("frame", static_cast<std::istream*>(&in));
  if (tiff == nullptr) return false;
  uint32_t w = 0, h = 0;
  uint16_t bits = 0, samples = 0;
  const bool ok = TIFFGetField(tiff, TIFFTAG_IMAGEWIDTH, &w) == 1 &&
                  TIFFGetField(tiff, TIFFTAG_IMAGELENGTH, &h) == 1 &&
                  TIFFGetFieldDefaulted(tiff, TIFFTAG_BITSPERSAMPLE, &bits) == 1 &&
                  TIFFGetFieldDefaulted(tiff, TIFFTAG_SAMPLESPERPIXEL, &samples) == 1 &&
                  w == static_cast<uint32_t>(width) && h == static_cast<uint32_t>(height) &&
                  bits == 16 && samples == 1 && !TIFFIsTiled(tiff);
  TIFFClose(tiff);
  return ok;
}

// The same for a PNG, from its IHDR chunk: width, height, bit depth 16, colour type 0 (gray).
bool PngDescribesFrame(const std::string& bytes, int width, int height) {
  if (bytes.size() < 26 || bytes.compare(12, 4, "IHDR") != 0) return false;
  const auto be32 = [&bytes](size_t at) {
    uint32_t v = 0;
    for (size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(bytes[at + k]);
    return v;
  };
  return be32(16) == static_cast<uint32_t>(width) && be32(20) == static_cast<uint32_t>(height) &&
         static_cast<unsigned char>(bytes[24]) == 16 && bytes[25] == 0;
}

}  // namespace

std::vector<uint16_t> DecodeFrameFile(const std::string& bytes, int width, int height,
                                      const std::string& what) {
  cv::Mat image;
  // Only the formats frames are written in (TIFF, and PNG from earlier versions) reach the
  // decoder: cv::imdecode would otherwise try every codec it has, and some (GDCM's DICOM reader)
  // abort on damaged input instead of failing (found by fuzz/frame_file_fuzz).
  const auto starts_with = [&bytes](std::string_view magic) {
    return bytes.size() >= magic.size() && std::string_view(bytes).substr(0, magic.size()) == magic;
  };
  const bool tiff = starts_with(std::string_view("II*\0", 4)) || starts_with(std::string_view("MM\0*", 4));
  const bool png = starts_with("\x89PNG\r\n\x1a\n");
  const bool expected = width > 0 && height > 0 &&
                        ((tiff && TiffDescribesFrame(bytes, width, height)) ||
                         (png && PngDescribesFrame(bytes, width, height)));
  if (expected && bytes.size() < (1u << 31)) {
    try {
      image = cv::imdecode(
          cv::Mat(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<char*>(bytes.data())),
          cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception&) {
      image = cv::Mat();  // reported below as not a frame
    }
  }
  if (image.empty() || image.type() != CV_16UC1 || image.cols != width || image.rows != height) {
    throw InputError(what + " is not the " + std::to_string(width) + "x" + std::to_string(height) +
                     " 16-bit single-channel image its journal line describes");
  }
  std::vector<uint16_t> samples(static_cast<size_t>(width) * height);
  for (int y = 0; y < height; ++y) {
    const uint16_t* row = image.ptr<uint16_t>(y);
    std::copy(row, row + width, samples.begin() + static_cast<size_t>(y) * width);
  }
  return samples;
}

}  // namespace zbrdf
