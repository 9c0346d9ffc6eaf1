#include "pictures/animated_png.h"

#include <zlib.h>

#include <cstdint>
#include <cstring>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "drivers/bgr_png.h"
#include "pictures/image.h"

namespace zbrdf {
namespace {

constexpr char kSignature[] = "\x89PNG\r\n\x1a\n";

void PutU32(std::string& out, uint32_t v) {
  out.push_back(static_cast<char>(v >> 24));
  out.push_back(static_cast<char>(v >> 16));
  out.push_back(static_cast<char>(v >> 8));
  out.push_back(static_cast<char>(v));
}

void PutU16(std::string& out, uint16_t v) {
  out.push_back(static_cast<char>(v >> 8));
  out.push_back(static_cast<char>(v));
}

uint32_t GetU32(const std::string& s, size_t at) {
  return static_cast<uint32_t>(static_cast<uint8_t>(s[at])) << 24 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[at + 1])) << 16 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[at + 2])) << 8 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[at + 3]));
}

void PutChunk(std::string& out, const char type[4], const std::string& data) {
  PutU32(out, static_cast<uint32_t>(data.size()));
  const std::string body = std::string(type, 4) + data;
  out += body;
  PutU32(out, static_cast<uint32_t>(
                  crc32(0L, reinterpret_cast<const Bytef*>(body.data()), body.size())));
}

struct Chunk {
  std::string type, data;
};

// The chunks of an encoded PNG (OpenCV's output: trusted, but checked).
std::vector<Chunk> ParseChunks(const std::string& png) {
  ZBRDF_ASSERT(png.compare(0, 8, std::string(kSignature, 8)) == 0, "not a PNG encoding");
  std::vector<Chunk> chunks;
  size_t at = 8;
  while (at + 12 <= png.size()) {
    const uint32_t length = GetU32(png, at);
    ZBRDF_ASSERT(at + 12 + length <= png.size(), "truncated PNG chunk");
    chunks.push_back({png.substr(at + 4, 4), png.substr(at + 8, length)});
    at += 12 + length;
  }
  return chunks;
}

}  // namespace

std::string EncodeAnimatedPng(const std::vector<cv::Mat>& frames, int fps) {
  if (frames.empty()) throw InputError("animated PNG: no frames to write");
  if (fps < 1 || fps > 120) {
    throw InputError("animated PNG: frame rate " + std::to_string(fps) +
                     " fps is out of range; give 1 to 120");
  }
  const int width = frames[0].cols, height = frames[0].rows;
  std::string out(kSignature, 8);
  uint32_t sequence = 0;
  for (size_t f = 0; f < frames.size(); ++f) {
    if (frames[f].cols != width || frames[f].rows != height || frames[f].type() != CV_8UC3) {
      throw InputError("animated PNG: frame " + std::to_string(f) +
                       " differs from frame 0 in size or type; every frame must be " +
                       std::to_string(width) + " x " + std::to_string(height) + " 8-bit BGR");
    }
    const std::vector<Chunk> chunks = ParseChunks(EncodeBgrPng(frames[f]));
    if (f == 0) {
      ZBRDF_ASSERT(!chunks.empty() && chunks[0].type == "IHDR", "PNG without IHDR first");
      PutChunk(out, "IHDR", chunks[0].data);
      std::string actl;
      PutU32(actl, static_cast<uint32_t>(frames.size()));
      PutU32(actl, 0);  // loop forever
      PutChunk(out, "acTL", actl);
    }
    std::string fctl;
    PutU32(fctl, sequence++);
    PutU32(fctl, static_cast<uint32_t>(width));
    PutU32(fctl, static_cast<uint32_t>(height));
    PutU32(fctl, 0);  // x offset
    PutU32(fctl, 0);  // y offset
    PutU16(fctl, 1);  // delay numerator
    PutU16(fctl, static_cast<uint16_t>(fps));  // delay denominator: 1/fps s
    fctl.push_back(0);  // dispose: none
    fctl.push_back(0);  // blend: source
    PutChunk(out, "fcTL", fctl);
    for (const Chunk& c : chunks) {
      if (c.type != "IDAT") continue;
      if (f == 0) {
        PutChunk(out, "IDAT", c.data);
      } else {
        std::string fdat;
        PutU32(fdat, sequence++);
        PutChunk(out, "fdAT", fdat + c.data);
      }
    }
  }
  PutChunk(out, "IEND", "");
  return out;
}

void WriteAnimatedPng(const std::string& path, const std::vector<cv::Mat>& frames, int fps) {
  WriteFileAtomically(path, EncodeAnimatedPng(frames, fps));
}

}  // namespace zbrdf
