#include "acquisition/frame_file.h"

#include <gtest/gtest.h>
#include <tiffio.h>

#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <tiffio.hxx>

#include "basis/error.h"
#include "basis/hash.h"
#include "basis/png.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

Frame RandomFrame(int width, int height, int bits, uint32_t seed) {
  Frame f;
  f.width = width;
  f.height = height;
  f.bit_depth = bits;
  f.layout = PixelLayout::kBayerRGGB;
  f.exposure_us = 1234.5;
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> value(0, (1 << bits) - 1);
  f.data.resize(static_cast<size_t>(width) * height);
  for (uint16_t& v : f.data) v = static_cast<uint16_t>(value(rng));
  return f;
}

TEST(FrameFile, RoundTripIsLossless) {
  // Odd sizes exercise a partial last strip; 16 bits exercise the full sample range.
  for (const auto& [w, h, bits] : {std::tuple{1360, 1024, 12}, std::tuple{37, 131, 16},
                                   std::tuple{1, 1, 8}}) {
    const Frame f = RandomFrame(w, h, bits, 7u + w);
    const std::string bytes = EncodeFrameFile(f);
    EXPECT_EQ(bytes.substr(0, 2), "II") << "a little-endian TIFF";
    EXPECT_EQ(DecodeFrameFile(bytes, w, h, "test frame"), f.data) << w << "x" << h;
  }
}

TEST(FrameFile, SameSamplesGiveSameBytes) {
  Frame a = RandomFrame(64, 48, 12, 3);
  Frame b = a;
  b.frame_id = 99;  // run-dependent fields must not reach the file
  b.timestamp_us = 123456;
  EXPECT_EQ(EncodeFrameFile(a), EncodeFrameFile(b));
}

TEST(FrameFile, OtherToolsReadIt) {
  // libtiff's strip interface (DecodeFrameFile reads scanlines) is another reader of the file:
  // 16-bit gray, and every sample as the frame has it.
  const Frame f = RandomFrame(200, 100, 12, 11);
  const std::string bytes = EncodeFrameFile(f);
  std::istringstream in(bytes);
  TIFF* tiff = TIFFStreamOpen("frame", static_cast<std::istream*>(&in));
  ASSERT_NE(tiff, nullptr);
  uint32_t width = 0, height = 0;
  uint16_t bits = 0;
  TIFFGetField(tiff, TIFFTAG_IMAGEWIDTH, &width);
  TIFFGetField(tiff, TIFFTAG_IMAGELENGTH, &height);
  TIFFGetField(tiff, TIFFTAG_BITSPERSAMPLE, &bits);
  EXPECT_EQ(width, 200u);
  EXPECT_EQ(height, 100u);
  EXPECT_EQ(bits, 16);
  std::vector<uint16_t> samples(f.data.size());
  tmsize_t read = 0;
  for (tstrip_t s = 0; s < TIFFNumberOfStrips(tiff); ++s) {
    const tmsize_t n = TIFFReadEncodedStrip(tiff, s, reinterpret_cast<char*>(samples.data()) + read,
                                            static_cast<tmsize_t>(samples.size() * 2) - read);
    ASSERT_GT(n, 0) << s;
    read += n;
  }
  TIFFClose(tiff);
  EXPECT_EQ(read, static_cast<tmsize_t>(samples.size() * 2));
  EXPECT_EQ(samples, f.data);
}

TEST(FrameFile, ReadsPngFramesOfOlderSessions) {
  const Frame f = RandomFrame(40, 30, 12, 5);
  PngImage image(40, 30, 1, 16);
  image.samples = f.data;
  const std::string png = EncodePng(image);
  EXPECT_EQ(DecodeFrameFile(png, 40, 30, "png"), f.data);
  // A PNG of the right size but 8 bits, or RGB, is not a frame.
  PngImage gray8(40, 30, 1, 8), rgb16(40, 30, 3, 16);
  EXPECT_THROW(DecodeFrameFile(EncodePng(gray8), 40, 30, "8-bit"), InputError);
  EXPECT_THROW(DecodeFrameFile(EncodePng(rgb16), 40, 30, "rgb"), InputError);
  EXPECT_THROW(DecodeFrameFile(png.substr(0, png.size() - 20), 40, 30, "cut"), InputError);
}

TEST(FrameFile, RejectsRgbAndMisSizedFrames) {
  Frame f = RandomFrame(8, 8, 12, 1);
  f.layout = PixelLayout::kRgb;
  EXPECT_THROW(EncodeFrameFile(f), DeviceError);
  f = RandomFrame(8, 8, 12, 1);
  f.data.pop_back();
  EXPECT_THROW(EncodeFrameFile(f), DeviceError);
}

TEST(FrameFile, GarbageTruncationAndWrongSizeAreInputErrors) {
  const Frame f = RandomFrame(64, 64, 12, 2);
  const std::string bytes = EncodeFrameFile(f);
  EXPECT_THROW(DecodeFrameFile("", 64, 64, "empty"), InputError);
  EXPECT_THROW(DecodeFrameFile("this is not an image", 64, 64, "text"), InputError);
  EXPECT_THROW(DecodeFrameFile(bytes.substr(0, 100), 64, 64, "truncated"), InputError);
  EXPECT_THROW(DecodeFrameFile(bytes, 32, 64, "wrong size"), InputError);
  // Bytes of another format, here with a DICOM tag: GDCM's reader asserted (aborted) on them when
  // frames were decoded by OpenCV (fuzz corpus regression-dicom-magic-aborts-gdcm).
  std::string dicom(132, '\0');
  dicom += "DICM";
  dicom += std::string("\x02\x00\x00\x00OB\xff\xff\x1d\x63", 12);
  EXPECT_THROW(DecodeFrameFile(dicom, 64, 64, "dicom"), InputError);
  // A damaged TIFF header made OpenCV allocate 3.9 GB (fuzz corpus
  // regression-strip-allocates-gigabytes): the header is checked against the journal's size first.
  std::ifstream damaged(ZBRDF_TEST_DATA_DIR "/fuzz/frame-allocates-gigabytes.tiff", std::ios::binary);
  ASSERT_TRUE(damaged.good());
  const std::string damaged_bytes((std::istreambuf_iterator<char>(damaged)), std::istreambuf_iterator<char>());
  EXPECT_THROW(DecodeFrameFile(damaged_bytes, 16, 12, "damaged"), InputError);
  try {
    DecodeFrameFile(bytes, 32, 64, "frame f000007.tiff");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("f000007.tiff"), std::string::npos) << e.what();
  }
}

// A frame as versions before the samples' checksum wrote it: the same TIFF, with the
// description "zbrdf raw frame: layout L, N significant bits, exposure E us" (libtiff directly).
std::string EncodeLikeEarlierVersions(const Frame& f) {
  std::ostringstream stream;
  TIFF* tiff = TIFFStreamOpen("frame", &stream);
  char description[160];
  std::snprintf(description, sizeof(description),
                "zbrdf raw frame: layout %s, %d significant bits, exposure %.3f us",
                PixelLayoutName(f.layout).c_str(), f.bit_depth, f.exposure_us);
  TIFFSetField(tiff, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(f.width));
  TIFFSetField(tiff, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(f.height));
  TIFFSetField(tiff, TIFFTAG_BITSPERSAMPLE, 16);
  TIFFSetField(tiff, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(tiff, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tiff, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tiff, TIFFTAG_COMPRESSION, COMPRESSION_ZSTD);
  TIFFSetField(tiff, TIFFTAG_ROWSPERSTRIP, f.height);
  TIFFSetField(tiff, TIFFTAG_IMAGEDESCRIPTION, description);
  TIFFWriteEncodedStrip(tiff, 0, const_cast<uint16_t*>(f.data.data()),
                        static_cast<tmsize_t>(f.data.size() * 2));
  TIFFClose(tiff);
  return stream.str();
}

TEST(FrameFile, EveryFrameRecordsTheChecksumOfItsSamples) {
  // XXH3 64 of the samples as little-endian words: {0x6261} is the bytes "ab" (xxhsum -H3 of a
  // file holding "ab" prints a873719c24d5735c; of an empty one, the specification's
  // 2d06800538d394c2). The FNV-1a 64 of frames written before XXH3 over the same bytes.
  EXPECT_EQ(FrameSamplesChecksum({}), 0x2d06800538d394c2ull);
  EXPECT_EQ(FrameSamplesChecksum({0x6261}), 0xa873719c24d5735cull);
  EXPECT_EQ(FrameSamplesFnv1a64({}), kFnv1a64Offset);
  EXPECT_EQ(FrameSamplesFnv1a64({0x6261}), Fnv1a64("ab"));
  const Frame f = RandomFrame(64, 48, 12, 21);
  const std::string bytes = EncodeFrameFile(f);
  char expected[80];
  std::snprintf(expected, sizeof(expected), "exposure 1234.500 us, samples xxh3-64:%016llx",
                static_cast<unsigned long long>(FrameSamplesChecksum(f.data)));
  EXPECT_NE(bytes.find(expected), std::string::npos) << "ImageDescription records the checksum";
}

// Frames written before XXH3 record "samples fnv1a64:<hex>": they read, checked with FNV-1a.
TEST(FrameFile, FramesRecordingFnv1aBeforeXxh3AreCheckedWithIt) {
  const Frame f = RandomFrame(64, 48, 12, 23);
  const std::string bytes = EncodeFrameFile(f);
  const size_t at = bytes.find("samples xxh3-64:");
  ASSERT_NE(at, std::string::npos);
  char fnv[40];
  std::snprintf(fnv, sizeof(fnv), "samples fnv1a64:%016llx",
                static_cast<unsigned long long>(FrameSamplesFnv1a64(f.data)));
  std::string old = bytes;
  old.replace(at, std::string(fnv).size(), fnv);  // the same length: the TIFF stays valid
  EXPECT_EQ(DecodeFrameFile(old, 64, 48, "old frame"), f.data);
  std::string wrong = old;
  char& digit = wrong[at + std::string(fnv).size() - 1];
  digit = digit == '0' ? '1' : '0';  // another hex digit
  try {
    DecodeFrameFile(wrong, 64, 48, "frame f000003.tiff");
    FAIL() << "samples that do not match the recorded FNV-1a checksum were read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frame f000003.tiff is damaged: its samples do not "
                                         "match the checksum the file records (fnv1a64:"),
              std::string::npos)
        << e.what();
  }
}

// Issue 15: "a bit flip inside a frame whose journal checksum is recomputed passes silently".
// The file's own checksum finds it: a decoded frame is either the original or an InputError.
TEST(FrameFile, BitFlipsInsideAFrameAreFoundFromTheFileAlone) {
  const Frame f = RandomFrame(64, 48, 12, 15);
  const std::string bytes = EncodeFrameFile(f);
  std::mt19937 rng(15);  // fixed seed: 300 flips over the whole file
  std::uniform_int_distribution<size_t> position(0, bytes.size() - 1);
  std::uniform_int_distribution<int> bit(0, 7);
  int rejected = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::string damaged = bytes;
    const size_t at = position(rng);
    damaged[at] = static_cast<char>(damaged[at] ^ (1 << bit(rng)));
    try {
      const std::vector<uint16_t> samples = DecodeFrameFile(damaged, 64, 48, "frame f.tiff");
      EXPECT_EQ(samples, f.data) << "a flip at byte " << at << " of " << bytes.size()
                                 << " gave other samples without an error";
    } catch (const InputError& e) {
      ++rejected;
      EXPECT_NE(std::string(e.what()).find("frame f.tiff"), std::string::npos) << e.what();
    }
  }
  // Most bytes are compressed samples (random 12-bit data barely compress); flips in unused
  // header bytes or strip padding change nothing.
  EXPECT_GT(rejected, 200);
  // The description of another frame over these samples: the samples do not match it.
  Frame other = f;
  other.data[5] ^= 1;
  const std::string other_bytes = EncodeFrameFile(other);
  const size_t a = bytes.find("xxh3-64:"), b = other_bytes.find("xxh3-64:");
  ASSERT_NE(a, std::string::npos);
  std::string swapped = bytes;
  swapped.replace(a, 24, other_bytes.substr(b, 24));
  try {
    DecodeFrameFile(swapped, 64, 48, "frame f000009.tiff");
    FAIL() << "samples that do not match the recorded checksum were read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frame f000009.tiff is damaged: its samples do not match "
                                         "the checksum the file records"),
              std::string::npos)
        << e.what();
  }
}

TEST(FrameFile, FramesOfEarlierVersionsWithoutTheChecksumStillRead) {
  const Frame f = RandomFrame(40, 30, 12, 8);
  const std::string old = EncodeLikeEarlierVersions(f);
  ASSERT_EQ(old.find("samples"), std::string::npos);
  EXPECT_EQ(DecodeFrameFile(old, 40, 30, "old frame"), f.data);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
