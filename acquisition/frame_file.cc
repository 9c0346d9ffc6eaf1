#include "acquisition/frame_file.h"

#include <bit>
#include <cstdio>
#include <sstream>
#include <string_view>

#include <tiffio.h>
#include <tiffio.hxx>

#include "basis/error.h"
#include "basis/hash.h"
#include "basis/png.h"

namespace zbrdf {

namespace {

constexpr char kDescriptionPrefix[] = "zbrdf raw frame: ";
constexpr char kSamplesKey[] = ", samples xxh3-64:";
constexpr char kSamplesKeyFnv1a[] = ", samples fnv1a64:";  // frames written before XXH3

}  // namespace

uint64_t FrameSamplesChecksum(const std::vector<uint16_t>& samples) {
  if constexpr (std::endian::native == std::endian::little) {
    return Xxh3_64(samples.data(), samples.size() * sizeof(uint16_t));
  } else {
    std::vector<unsigned char> bytes(2 * samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
      bytes[2 * i] = static_cast<unsigned char>(samples[i] & 0xff);
      bytes[2 * i + 1] = static_cast<unsigned char>(samples[i] >> 8);
    }
    return Xxh3_64(bytes.data(), bytes.size());
  }
}

uint64_t FrameSamplesFnv1a64(const std::vector<uint16_t>& samples) {
  uint64_t h = kFnv1a64Offset;
  for (uint16_t v : samples) {
    const unsigned char bytes[2] = {static_cast<unsigned char>(v & 0xff),
                                    static_cast<unsigned char>(v >> 8)};
    h = Fnv1a64(bytes, 2, h);
  }
  return h;
}

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
  char description[200];
  std::snprintf(description, sizeof(description),
                "%slayout %s, %d significant bits, exposure %.3f us%s%016llx", kDescriptionPrefix,
                PixelLayoutName(frame.layout).c_str(), frame.bit_depth, frame.exposure_us,
                kSamplesKey, static_cast<unsigned long long>(FrameSamplesChecksum(frame.data)));
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

// A TIFF frame's samples, read with libtiff: true, the width x height samples in *samples and its
// ImageDescription in *description ("" if it has none), when its first directory describes the
// expected frame (width x height, one 16-bit sample per pixel, in strips) and every row decodes.
// The header is checked before any pixel buffer is allocated: a few damaged header bytes can
// otherwise declare gigabytes (found by fuzz/frame_file_fuzz).
bool ReadTiffFrame(const std::string& bytes, int width, int height, std::string* description,
                   std::vector<uint16_t>* samples) {
  std::istringstream in(bytes);
  TIFF* tiff = TIFFStreamOpen("frame", static_cast<std::istream*>(&in));
  if (tiff == nullptr) return false;
  uint32_t w = 0, h = 0;
  uint16_t bits = 0, per_pixel = 0, planar = 0;
  char* text = nullptr;
  description->clear();
  if (TIFFGetField(tiff, TIFFTAG_IMAGEDESCRIPTION, &text) == 1 && text != nullptr) {
    *description = text;
  }
  bool ok = TIFFGetField(tiff, TIFFTAG_IMAGEWIDTH, &w) == 1 &&
            TIFFGetField(tiff, TIFFTAG_IMAGELENGTH, &h) == 1 &&
            TIFFGetFieldDefaulted(tiff, TIFFTAG_BITSPERSAMPLE, &bits) == 1 &&
            TIFFGetFieldDefaulted(tiff, TIFFTAG_SAMPLESPERPIXEL, &per_pixel) == 1 &&
            TIFFGetFieldDefaulted(tiff, TIFFTAG_PLANARCONFIG, &planar) == 1 &&
            w == static_cast<uint32_t>(width) && h == static_cast<uint32_t>(height) && bits == 16 &&
            per_pixel == 1 && planar == PLANARCONFIG_CONTIG && !TIFFIsTiled(tiff) &&
            TIFFScanlineSize64(tiff) == static_cast<uint64_t>(width) * sizeof(uint16_t);
  if (ok) {
    // Row by row (libtiff decompresses each strip once, and swaps big-endian files' bytes).
    samples->assign(static_cast<size_t>(width) * height, 0);
    for (int y = 0; ok && y < height; ++y) {
      ok = TIFFReadScanline(tiff, samples->data() + static_cast<size_t>(y) * width,
                            static_cast<uint32_t>(y)) == 1;
    }
  }
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

// The same for a PNG (frames of earlier versions): 16-bit gray, width x height, undamaged. The
// IHDR PngDescribesFrame checks is the one the decoder reads, so the image has that shape.
bool ReadPngFrame(const std::string& bytes, int width, int height, std::vector<uint16_t>* samples) {
  if (!PngDescribesFrame(bytes, width, height)) return false;
  try {
    *samples = DecodePng(bytes, "frame").samples;
    return true;
  } catch (const InputError&) {
    return false;
  }
}

// The checksum a frame file's ImageDescription records: true, *checksum and its algorithm for a
// frame written with one (XXH3, or FNV-1a before XXH3); true and kNone for a frame of an earlier
// version (the description without it, or none); false for a description that is neither
// (damaged).
enum class SamplesHash { kNone, kXxh3, kFnv1a };

bool ParseDescription(const std::string& description, SamplesHash* hash, uint64_t* checksum) {
  *hash = SamplesHash::kNone;
  if (description.empty()) return true;
  const std::string prefix = kDescriptionPrefix;
  if (description.compare(0, prefix.size(), prefix) != 0) return false;
  size_t at = description.find(kSamplesKey);
  size_t key_size = std::string_view(kSamplesKey).size();
  SamplesHash found = SamplesHash::kXxh3;
  if (at == std::string::npos) {
    at = description.find(kSamplesKeyFnv1a);
    key_size = std::string_view(kSamplesKeyFnv1a).size();
    found = SamplesHash::kFnv1a;
  }
  if (at == std::string::npos) {
    // Earlier versions: "zbrdf raw frame: layout L, N significant bits, exposure E us".
    char layout[32];
    int bits = 0;
    double exposure = 0;
    int consumed = 0;
    return std::sscanf(description.c_str() + prefix.size(),
                       "layout %31[a-z-], %d significant bits, exposure %lf us%n", layout, &bits,
                       &exposure, &consumed) == 3 &&
           prefix.size() + consumed == description.size();
  }
  const std::string hex = description.substr(at + key_size);
  if (hex.size() != 16 || hex.find_first_not_of("0123456789abcdef") != std::string::npos) {
    return false;
  }
  *hash = found;
  *checksum = std::stoull(hex, nullptr, 16);
  return true;
}

}  // namespace

std::vector<uint16_t> DecodeFrameFile(const std::string& bytes, int width, int height,
                                      const std::string& what) {
  // Only the formats frames are written in (TIFF, and PNG from earlier versions) are decoded,
  // each by its own library.
  const auto starts_with = [&bytes](std::string_view magic) {
    return bytes.size() >= magic.size() && std::string_view(bytes).substr(0, magic.size()) == magic;
  };
  const bool tiff = starts_with(std::string_view("II*\0", 4)) || starts_with(std::string_view("MM\0*", 4));
  const bool png = starts_with("\x89PNG\r\n\x1a\n");
  std::string description;
  std::vector<uint16_t> samples;
  const bool read = width > 0 && height > 0 &&
                    ((tiff && ReadTiffFrame(bytes, width, height, &description, &samples)) ||
                     (png && ReadPngFrame(bytes, width, height, &samples)));
  if (!read) {
    throw InputError(what + " is not the " + std::to_string(width) + "x" + std::to_string(height) +
                     " 16-bit single-channel image its journal line describes");
  }
  SamplesHash hash = SamplesHash::kNone;
  uint64_t checksum = 0;
  if (!ParseDescription(description, &hash, &checksum)) {
    throw InputError(what + " is damaged: its TIFF ImageDescription is not a zbrdf frame's");
  }
  if (hash != SamplesHash::kNone) {
    const bool xxh3 = hash == SamplesHash::kXxh3;
    const uint64_t actual = xxh3 ? FrameSamplesChecksum(samples) : FrameSamplesFnv1a64(samples);
    if (actual != checksum) {
      const char* name = xxh3 ? "xxh3-64" : "fnv1a64";
      char text[96];
      std::snprintf(text, sizeof(text), " (%s:%016llx, the file records %s:%016llx)", name,
                    static_cast<unsigned long long>(actual), name,
                    static_cast<unsigned long long>(checksum));
      throw InputError(what +
                       " is damaged: its samples do not match the checksum the file "
                       "records" +
                       text);
    }
  }
  return samples;
}

}  // namespace zbrdf
