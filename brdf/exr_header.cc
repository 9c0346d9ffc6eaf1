#include "brdf/exr_header.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <vector>

#include "basis/error.h"

namespace zbrdf {
namespace {

// Bytes OpenEXR 3.1 reads for attribute types of a fixed size, whatever size the file declares.
const std::map<std::string, int32_t>& FixedSizes() {
  static const std::map<std::string, int32_t> sizes = {
      {"box2i", 16},   {"box2f", 16},  {"chromaticities", 32}, {"compression", 1},
      {"double", 8},   {"envmap", 1},  {"float", 4},           {"int", 4},
      {"keycode", 28}, {"lineOrder", 1}, {"m33f", 36},         {"m33d", 72},
      {"m44f", 64},    {"m44d", 128},  {"rational", 8},        {"tiledesc", 9},
      {"timecode", 8}, {"v2i", 8},     {"v2f", 8},             {"v2d", 16},
      {"v3i", 12},     {"v3f", 12},    {"v3d", 24},            {"deepImageState", 1}};
  return sizes;
}

// Scan lines per chunk of a scanline part, by OpenEXR's compression code (the file format's
// table: NONE, RLE, ZIPS 1; ZIP, PXR24 16; PIZ, B44, B44A, DWAA 32; DWAB 256); 0 for a code
// OpenEXR does not know (it reports that itself).
int64_t LinesPerChunk(int compression) {
  constexpr int64_t kLines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
  return compression >= 0 && compression < 10 ? kLines[compression] : 0;
}

int32_t Int32At(const char* p) {
  int32_t v;
  std::memcpy(&v, p, 4);  // little-endian, as is every EXR integer
  return v;
}

}  // namespace

void CheckExrHeaderSizes(const std::string& path, const std::string& what) {
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) return;
  const int64_t file_size = static_cast<int64_t>(file.tellg());
  // Our headers are a few KB (zbrdf.info JSON included); reading more would only cost time on a
  // large zonal.exr. Headers reaching past what was read are left to OpenEXR.
  constexpr int64_t kMaxHeaderBytes = 1 << 20;
  std::vector<char> head(static_cast<size_t>(std::clamp<int64_t>(file_size, 0, kMaxHeaderBytes)));
  file.seekg(0);
  if (!file.read(head.data(), static_cast<std::streamsize>(head.size()))) return;
  constexpr unsigned char kMagic[4] = {0x76, 0x2f, 0x31, 0x01};
  if (head.size() < 8 || std::memcmp(head.data(), kMagic, 4) != 0) return;
  const bool multipart = (static_cast<unsigned char>(head[5]) & 0x10) != 0;  // version bit 12
  const auto fail = [&](const std::string& attribute, const std::string& problem) {
    throw InputError(what + ": OpenEXR header attribute '" + attribute + "' " + problem +
                     "; the file is truncated or corrupt");
  };
  // Pixel data a part may declare: what the file could hold at any compression OpenEXR offers
  // (ZIP stops near 1000:1), and never less than 64 MB.
  const int64_t max_pixel_bytes = std::max<int64_t>(int64_t{1} << 26, 2048 * file_size);

  size_t pos = 8;
  // A NUL-terminated name of at most 255 characters; false at the end of what was read.
  auto read_name = [&](std::string* name) {
    const size_t end = std::find(head.begin() + static_cast<ptrdiff_t>(pos), head.end(), '\0') -
                       head.begin();
    if (end >= head.size() || end - pos > 255) return false;
    name->assign(head.data() + pos, end - pos);
    pos = end + 1;
    return true;
  };
  // A single-part file's version field says whether it is tiled (bit 9); a multi-part file's
  // parts say so in their 'type' attribute.
  const bool single_part_tiled = (static_cast<unsigned char>(head[5]) & 0x02) != 0;
  for (int part = 0;; ++part) {
    if (part > 0 && (!multipart || pos >= head.size() || head[pos] == '\0')) return;
    int64_t width = 0, height = 0, bytes_per_pixel = 0;
    int compression = -1;            // the 'compression' attribute's value, if read
    int64_t tile_x = 0, tile_y = 0;  // the 'tiles' attribute's tile size, if any
    bool tiled = !multipart && single_part_tiled;
    for (;;) {
      std::string name, type;
      if (!read_name(&name)) return;
      if (name.empty()) break;  // end of this part's header
      if (!read_name(&type) || pos + 4 > head.size()) return;
      const int32_t size = Int32At(head.data() + pos);
      pos += 4;
      if (size < 0 || size > file_size - static_cast<int64_t>(pos)) {
        fail(name, "declares " + std::to_string(size) + " bytes but the file has " +
                       std::to_string(file_size - static_cast<int64_t>(pos)) + " left");
      }
      if (pos + static_cast<size_t>(size) > head.size()) return;
      const char* value = head.data() + pos;
      // OpenEXR reads some types by their own layout rather than by the declared size; where
      // the two disagree it would go on reading from the wrong place, so they must agree.
      if (const auto fixed = FixedSizes().find(type); fixed != FixedSizes().end()) {
        if (size != fixed->second) {
          fail(name, "of type " + type + " has " + std::to_string(size) + " bytes, not " +
                         std::to_string(fixed->second));
        }
      } else if (type == "chlist") {  // per channel: name, int32 type, 4 bytes, 2 x int32
        size_t p = 0;
        for (;;) {
          const char* end = static_cast<const char*>(std::memchr(value + p, '\0', size - p));
          if (end == nullptr) fail(name, "(a channel list) is not terminated");
          const size_t name_length = static_cast<size_t>(end - (value + p));
          p += name_length + 1;
          if (name_length == 0) break;
          if (p + 16 > static_cast<size_t>(size)) fail(name, "(a channel list) is cut short");
          const int32_t pixel_type = Int32At(value + p);
          bytes_per_pixel += pixel_type == 1 ? 2 : 4;  // HALF; UINT and FLOAT
          p += 16;
        }
        if (p != static_cast<size_t>(size)) fail(name, "(a channel list) has trailing bytes");
      } else if (type == "stringvector") {  // int32 length, then the characters, repeated
        for (size_t p = 0; p < static_cast<size_t>(size);) {
          if (p + 4 > static_cast<size_t>(size)) fail(name, "(a string list) is cut short");
          const int32_t length = Int32At(value + p);
          p += 4;
          if (length < 0 || static_cast<size_t>(length) > size - p) {
            fail(name, "(a string list) has a string longer than the attribute");
          }
          p += static_cast<size_t>(length);
        }
      } else if (type == "preview") {  // uint32 width, uint32 height, 4 bytes per pixel
        uint32_t w = 0, h = 0;
        if (size >= 8) {
          std::memcpy(&w, value, 4);
          std::memcpy(&h, value + 4, 4);
        }
        if (size < 8 || uint64_t{w} * h * 4 != static_cast<uint64_t>(size) - 8) {
          fail(name, "(a preview image) does not match its size");
        }
      } else if (type == "idmanifest") {  // compressed, with its own declared sizes
        fail(name, "is an ID manifest, which zbrdf's files never hold");
      }
      if (name == "dataWindow" && type == "box2i") {
        const int64_t x0 = Int32At(value), y0 = Int32At(value + 4);
        const int64_t x1 = Int32At(value + 8), y1 = Int32At(value + 12);
        width = x1 - x0 + 1;
        height = y1 - y0 + 1;
        if (width < 1 || height < 1 || width > (1 << 24) || height > (1 << 24)) {
          fail(name, "is " + std::to_string(width) + " x " + std::to_string(height) + " pixels");
        }
      }
      if (name == "compression" && type == "compression") {
        compression = static_cast<unsigned char>(value[0]);
      }
      if (name == "tiles" && type == "tiledesc") {
        tile_x = static_cast<uint32_t>(Int32At(value));
        tile_y = static_cast<uint32_t>(Int32At(value + 4));
      }
      if (name == "type" && type == "string") {
        const std::string part_type(value, static_cast<size_t>(size));
        tiled = part_type == "tiledimage" || part_type == "deeptile";
      }
      if (name == "chunkCount" && type == "int") {
        const int32_t chunks = Int32At(value);
        if (chunks < 0 || chunks > file_size / 8) {  // each chunk has an 8-byte offset
          fail(name, "is " + std::to_string(chunks) + ", more chunks than the file can hold");
        }
      }
      pos += static_cast<size_t>(size);
    }
    // A part's chunks: a scanline part's blocks of `lines` lines (its compression's block: 1, 16,
    // 32 or 256; 0 for a code OpenEXR does not know, which it reports itself), a tiled part's
    // tiles of its full-resolution level (at least; none counted without a tile size).
    const int64_t lines = tiled ? 0 : LinesPerChunk(compression);
    const bool has_tiles = tiled && tile_x > 0 && tile_y > 0;
    // OpenEXR reads (and first allocates, and zeroes) a table of one 8-byte offset per chunk
    // before any pixel. A table that cannot fit in the file means a damaged header, and reading
    // it would cost up to 128 MB (2^24 single-line chunks) before OpenEXR found the file short.
    if (width > 0 && height > 0) {
      int64_t chunks = 0;
      if (has_tiles) {
        chunks = ((width + tile_x - 1) / tile_x) * ((height + tile_y - 1) / tile_y);
      } else if (lines > 0) {
        chunks = (height + lines - 1) / lines;
      }
      if (chunks > file_size / 8) {
        throw InputError(what + ": an image part of " + std::to_string(width) + " x " +
                         std::to_string(height) + " pixels has " + std::to_string(chunks) +
                         " chunks, whose offset table alone (8 bytes each) is larger than the " +
                         std::to_string(file_size) +
                         "-byte file; the file is truncated or corrupt");
      }
    }
    // OpenEXR reads a part a chunk at a time, and its line buffers and compressors are sized for
    // a whole chunk whatever the image's height: a one-line image under ZIP gets 16 lines'
    // buffers, a tiled one a whole tile's. So the pixel bytes a part may make OpenEXR allocate
    // (and zero) count whole chunks: found by profiling fuzz/dbrdf_file_fuzz, a 552-byte file
    // declaring one line 2^24 pixels wide under ZIP took 11 s and 2 GB to be refused by OpenEXR.
    // In double: tile sizes are any uint32, whose products overflow 64 bits.
    const double w = static_cast<double>(width);
    double buffered_pixels = w * static_cast<double>(height);
    if (has_tiles) {
      buffered_pixels =
          std::max(buffered_pixels, static_cast<double>(tile_x) * static_cast<double>(tile_y));
    } else if (lines > 0) {
      buffered_pixels = w * static_cast<double>((height + lines - 1) / lines * lines);
    }
    if (buffered_pixels * static_cast<double>(bytes_per_pixel) >
        static_cast<double>(max_pixel_bytes)) {
      throw InputError(what + ": an image part declares " + std::to_string(width) + " x " +
                       std::to_string(height) + " pixels of " + std::to_string(bytes_per_pixel) +
                       " bytes (read " + (tiled ? "a tile" : "a block of lines") +
                       " at a time), far more than a " + std::to_string(file_size) +
                       "-byte file can hold; the file is corrupt");
    }
  }
}

void RequireWindowAtOrigin(int min_x, int min_y, int max_x, int max_y, const std::string& what,
                           const std::string& part) {
  if (min_x != 0 || min_y != 0 || max_x < 0 || max_y < 0) {
    std::string message = what;
    message += ": the ";
    message += part;
    message += " part's data window [";
    message += std::to_string(min_x) + ", " + std::to_string(min_y) + "] - [";
    message += std::to_string(max_x) + ", " + std::to_string(max_y);
    message += "] does not start at (0, 0) as zbrdf writes it; the file is damaged or not ours";
    throw InputError(message);
  }
}

}  // namespace zbrdf
