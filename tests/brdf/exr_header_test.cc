#include "brdf/exr_header.h"

#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfTiledOutputFile.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "basis/error.h"
#include "tests/test_files.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::TempDir;

constexpr int kWidth = 4, kHeight = 3;

// A kWidth x kHeight single-channel FLOAT file written by OpenEXR itself: scanlines under
// `compression`, or 2 x 2 tiles.
std::string WriteSmallExr(const TempDir& dir, const std::string& name, Imf::Compression compression,
                          bool tiled) {
  const std::string path = dir.File(name);
  std::vector<float> pixels(kWidth * kHeight, 0.5f);
  Imf::Header header(kWidth, kHeight);
  header.compression() = compression;
  header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
  Imf::FrameBuffer fb;
  fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(pixels.data()), sizeof(float),
                            sizeof(float) * kWidth));
  if (tiled) {
    header.setTileDescription(Imf::TileDescription(2, 2, Imf::ONE_LEVEL));
    Imf::TiledOutputFile out(path.c_str(), header);
    out.setFrameBuffer(fb);
    out.writeTiles(0, out.numXTiles() - 1, 0, out.numYTiles() - 1);
  } else {
    Imf::OutputFile out(path.c_str(), header);
    out.setFrameBuffer(fb);
    out.writePixels(kHeight);
  }
  return path;
}

// Rewrites one int32 of the data window (the box2i's min x, min y, max x, max y: `index` 0-3)
// of the file at `path`, which WriteSmallExr wrote.
void SetDataWindow(const std::string& path, int index, int32_t value) {
  std::string bytes = testing::ReadFile(path);
  const std::string key("dataWindow\0box2i\0", 17);
  const size_t at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  const size_t field = at + key.size() + 4 + 4 * static_cast<size_t>(index);  // past the size
  int32_t previous = 0;
  std::memcpy(&previous, bytes.data() + field, 4);
  ASSERT_EQ(previous, index == 2 ? kWidth - 1 : index == 3 ? kHeight - 1 : 0);
  std::memcpy(bytes.data() + field, &value, 4);
  testing::WriteFile(path, bytes);
}
void SetLastRow(const std::string& path, int32_t max_y) { SetDataWindow(path, 3, max_y); }
void SetLastColumn(const std::string& path, int32_t max_x) { SetDataWindow(path, 2, max_x); }

// The message of the InputError CheckExrHeaderSizes throws, or "" if it does not throw.
std::string CheckMessage(const std::string& path) {
  try {
    CheckExrHeaderSizes(path, "test file " + path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ExrHeader, FilesOpenExrWroteAreAccepted) {
  const TempDir dir("exr-header-valid");
  for (const Imf::Compression c :
       {Imf::NO_COMPRESSION, Imf::ZIPS_COMPRESSION, Imf::ZIP_COMPRESSION, Imf::PIZ_COMPRESSION}) {
    EXPECT_EQ(CheckMessage(WriteSmallExr(dir, "scanline.exr", c, false)), "") << c;
  }
  EXPECT_EQ(CheckMessage(WriteSmallExr(dir, "tiled.exr", Imf::ZIP_COMPRESSION, true)), "");
}

// Found by fuzz/dbrdf_file_fuzz: a few hundred bytes declaring 2^24 scan lines made OpenEXR
// allocate and zero a 128 MB chunk-offset table before it found the file short; most of that
// target's time went there.
TEST(ExrHeader, AnOffsetTableLargerThanTheFileIsAnInputError) {
  const TempDir dir("exr-header-offsets");
  const std::string zips = WriteSmallExr(dir, "zips.exr", Imf::ZIPS_COMPRESSION, false);
  const int64_t size = static_cast<int64_t>(std::filesystem::file_size(zips));
  // ZIPS: one line per chunk, so size / 8 lines still fit their offsets and one more does not.
  SetLastRow(zips, static_cast<int32_t>(size / 8 - 1));
  EXPECT_EQ(CheckMessage(zips), "");
  const std::string zips2 = WriteSmallExr(dir, "zips2.exr", Imf::ZIPS_COMPRESSION, false);
  SetLastRow(zips2, static_cast<int32_t>(size / 8));
  const std::string message = CheckMessage(zips2);
  EXPECT_NE(message.find("test file " + zips2), std::string::npos) << message;
  EXPECT_NE(message.find(std::to_string(size / 8 + 1) + " chunks"), std::string::npos) << message;
  EXPECT_NE(message.find("offset table"), std::string::npos) << message;

  // ZIP: 16 lines per chunk, so 16 times as many lines fit.
  const std::string zip = WriteSmallExr(dir, "zip.exr", Imf::ZIP_COMPRESSION, false);
  const int64_t zip_size = static_cast<int64_t>(std::filesystem::file_size(zip));
  SetLastRow(zip, static_cast<int32_t>(16 * (zip_size / 8) - 1));
  EXPECT_EQ(CheckMessage(zip), "");
  const std::string zip2 = WriteSmallExr(dir, "zip2.exr", Imf::ZIP_COMPRESSION, false);
  SetLastRow(zip2, static_cast<int32_t>(16 * (zip_size / 8)));
  EXPECT_NE(CheckMessage(zip2).find("offset table"), std::string::npos);

  // Tiled: at least one chunk per 2 x 2 tile of the full-resolution level.
  const std::string tiled = WriteSmallExr(dir, "tiled.exr", Imf::ZIP_COMPRESSION, true);
  const int64_t tiled_size = static_cast<int64_t>(std::filesystem::file_size(tiled));
  const int64_t tile_rows = tiled_size / 8 / 2 + 1;  // 2 tiles per row of tiles (4 pixels wide)
  SetLastRow(tiled, static_cast<int32_t>(2 * tile_rows - 1));
  EXPECT_NE(CheckMessage(tiled).find("offset table"), std::string::npos);
}

// Found by profiling fuzz/dbrdf_file_fuzz: a 552-byte file declaring a single line 2^24 pixels
// wide under ZIP passed the pixel-bytes bound (64 MB for a file this small), but OpenEXR sizes its
// line buffers and its compressor's for a whole 16-line chunk, so it allocated and zeroed ~2 GB
// (11 s under ASan) before refusing the file. The bound counts whole chunks.
TEST(ExrHeader, PixelBytesAreCountedOverWholeChunks) {
  const TempDir dir("exr-header-chunk-bytes");
  // 2^22 x 3 one-float pixels: 48 MB, under the 64 MB bound. One line per chunk (ZIPS), that is
  // what OpenEXR buffers; 16 lines per chunk (ZIP), it buffers 16 x 2^22 x 4 bytes = 256 MB.
  constexpr int32_t kWide = (1 << 22) - 1;
  const std::string zips = WriteSmallExr(dir, "zips.exr", Imf::ZIPS_COMPRESSION, false);
  SetLastColumn(zips, kWide);
  EXPECT_EQ(CheckMessage(zips), "");
  const std::string zip = WriteSmallExr(dir, "zip.exr", Imf::ZIP_COMPRESSION, false);
  SetLastColumn(zip, kWide);
  const std::string message = CheckMessage(zip);
  EXPECT_NE(message.find("test file " + zip), std::string::npos) << message;
  EXPECT_NE(message.find("4194304 x 3 pixels of 4 bytes (read a block of lines at a time)"),
            std::string::npos)
      << message;
  // Under the bound at ZIP too: 2^20 x 16 lines x 4 bytes = 64 MB exactly.
  const std::string zip_at_bound = WriteSmallExr(dir, "zip-bound.exr", Imf::ZIP_COMPRESSION, false);
  SetLastColumn(zip_at_bound, (1 << 20) - 1);
  EXPECT_EQ(CheckMessage(zip_at_bound), "");
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
