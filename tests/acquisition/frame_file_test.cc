#include "acquisition/frame_file.h"

#include <fstream>
#include <iterator>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "basis/error.h"

namespace zbrdf {
namespace {

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
  // OpenCV's TIFF reader (libtiff) is an independent decoder of the same file.
  const Frame f = RandomFrame(200, 100, 12, 11);
  const std::string bytes = EncodeFrameFile(f);
  const cv::Mat image =
      cv::imdecode(std::vector<uchar>(bytes.begin(), bytes.end()), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(image.type(), CV_16UC1);
  ASSERT_EQ(image.cols, 200);
  EXPECT_EQ(image.at<uint16_t>(57, 133), f.data[57 * 200 + 133]);
}

TEST(FrameFile, ReadsPngFramesOfOlderSessions) {
  const Frame f = RandomFrame(40, 30, 12, 5);
  std::vector<uchar> png;
  cv::Mat image(30, 40, CV_16UC1, const_cast<uint16_t*>(f.data.data()));
  ASSERT_TRUE(cv::imencode(".png", image, png));
  EXPECT_EQ(DecodeFrameFile(std::string(png.begin(), png.end()), 40, 30, "png"), f.data);
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
  // Bytes of another format OpenCV knows, here with a DICOM tag: GDCM's reader asserts (aborts)
  // on them, so they must not reach cv::imdecode (fuzz corpus regression-dicom-magic-aborts-gdcm).
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

}  // namespace
}  // namespace zbrdf
