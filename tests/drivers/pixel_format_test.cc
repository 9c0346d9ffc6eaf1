#include "drivers/pixel_format.h"

#include <gtest/gtest.h>

#include <random>

#include "basis/error.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

std::vector<uint16_t> Unpack(const char* name, std::vector<uint8_t> bytes, int width, int height) {
  const PixelFormatInfo* format = FindPixelFormat(name);
  EXPECT_NE(format, nullptr) << name;
  std::vector<uint16_t> samples;
  UnpackPixels(*format, bytes.data(), bytes.size(), width, height, &samples);
  return samples;
}

// The expected values below are written from the format definitions quoted in pixel_format.h,
// not computed by the code under test.
TEST(PixelFormatTest, GigEVisionPacked12MatchesTheSpecLayout) {
  // P0 = 0xABC, P1 = 0x123: B0 = P0[11:4], B1 = P1[3:0] << 4 | P0[3:0], B2 = P1[11:4].
  EXPECT_EQ(Unpack("Mono12Packed", {0xAB, 0x3C, 0x12}, 2, 1),
            (std::vector<uint16_t>{0xABC, 0x123}));
  // {FF F0 00}: P0 = FF << 4 | 0 = 0xFF0, P1 = 00 << 4 | F = 0x00F;
  // {00 0F FF}: P2 = 00 << 4 | F = 0x00F, P3 = FF << 4 | 0 = 0xFF0.
  EXPECT_EQ(Unpack("BayerRG12Packed", {0xFF, 0xF0, 0x00, 0x00, 0x0F, 0xFF}, 4, 1),
            (std::vector<uint16_t>{0xFF0, 0x00F, 0x00F, 0xFF0}));
}

TEST(PixelFormatTest, Pfnc12pMatchesTheSpecLayout) {
  // LSB-first bit stream: B0 = P0[7:0], B1 = P1[3:0] << 4 | P0[11:8], B2 = P1[11:4].
  EXPECT_EQ(Unpack("Mono12p", {0xBC, 0x3A, 0x12}, 2, 1), (std::vector<uint16_t>{0xABC, 0x123}));
  EXPECT_EQ(Unpack("BayerRG12p", {0x01, 0x00, 0x80}, 2, 1), (std::vector<uint16_t>{0x001, 0x800}));
}

TEST(PixelFormatTest, SixteenBitContainersAreLittleEndianAndMasked) {
  EXPECT_EQ(Unpack("Mono16", {0x34, 0x12, 0xFF, 0xFF}, 2, 1),
            (std::vector<uint16_t>{0x1234, 0xFFFF}));
  EXPECT_EQ(Unpack("BayerGB16", {0x01, 0x80}, 1, 1), (std::vector<uint16_t>{0x8001}));
  // Mono12: the value sits in the low 12 bits.
  EXPECT_EQ(Unpack("Mono12", {0xBC, 0x0A, 0xFF, 0x0F}, 2, 1),
            (std::vector<uint16_t>{0xABC, 0xFFF}));
  EXPECT_EQ(Unpack("BayerBG10", {0xFF, 0x03}, 1, 1), (std::vector<uint16_t>{0x3FF}));
}

TEST(PixelFormatTest, EightBitAndColorFormats) {
  EXPECT_EQ(Unpack("Mono8", {0, 7, 255}, 3, 1), (std::vector<uint16_t>{0, 7, 255}));
  EXPECT_EQ(Unpack("RGB8", {1, 2, 3, 4, 5, 6}, 2, 1), (std::vector<uint16_t>{1, 2, 3, 4, 5, 6}));
  // BGR8 arrives as B, G, R and is delivered as R, G, B.
  EXPECT_EQ(Unpack("BGR8", {1, 2, 3}, 1, 1), (std::vector<uint16_t>{3, 2, 1}));
}

TEST(PixelFormatTest, LayoutsAndDepthsFollowTheFormatNames) {
  EXPECT_EQ(FindPixelFormat("BayerRG12")->layout, PixelLayout::kBayerRGGB);
  EXPECT_EQ(FindPixelFormat("BayerGR16")->layout, PixelLayout::kBayerGRBG);
  EXPECT_EQ(FindPixelFormat("BayerGB8")->layout, PixelLayout::kBayerGBRG);
  EXPECT_EQ(FindPixelFormat("BayerBG12p")->layout, PixelLayout::kBayerBGGR);
  EXPECT_EQ(FindPixelFormat("Mono16")->bit_depth, 16);
  EXPECT_EQ(FindPixelFormat("Mono12Packed")->bit_depth, 12);
  EXPECT_EQ(FindPixelFormat(0x0110002fu)->name, std::string("BayerRG16"));
  EXPECT_EQ(FindPixelFormat("YUV422Packed"), nullptr);
  // The PFNC code carries bits per pixel in bits 16-23; the table must agree with it.
  for (const auto& f : SupportedPixelFormats()) {
    const int bits_per_pixel = static_cast<int>((f.pfnc >> 16) & 0xFF);
    EXPECT_EQ(PayloadBytes(f, 8, 2), static_cast<size_t>(8 * 2 * bits_per_pixel / 8)) << f.name;
  }
}

TEST(PixelFormatTest, TruncatedPayloadThrowsInsteadOfBecomingAFrame) {
  const PixelFormatInfo* format = FindPixelFormat("Mono16");
  std::vector<uint8_t> bytes(2 * 4 * 4 - 1);
  std::vector<uint16_t> samples;
  EXPECT_THROW(UnpackPixels(*format, bytes.data(), bytes.size(), 4, 4, &samples), DeviceError);
}

TEST(PixelFormatTest, PackIsTheInverseOfUnpackForEveryFormat) {
  std::mt19937 rng(7);
  for (const auto& f : SupportedPixelFormats()) {
    const int width = 6, height = 4;
    std::uniform_int_distribution<int> level(0, (1 << f.bit_depth) - 1);
    std::vector<uint16_t> samples(static_cast<size_t>(width * height * SamplesPerPixel(f.layout)));
    for (auto& s : samples) s = static_cast<uint16_t>(level(rng));
    std::vector<uint8_t> bytes(PayloadBytes(f, width, height));
    PackPixels(f, samples, width, height, bytes.data());
    std::vector<uint16_t> back;
    UnpackPixels(f, bytes.data(), bytes.size(), width, height, &back);
    EXPECT_EQ(back, samples) << f.name;
  }
}

TEST(PixelFormatTest, PackRejectsSamplesAboveTheBitDepth) {
  const PixelFormatInfo* format = FindPixelFormat("Mono12");
  std::vector<uint8_t> bytes(2);
  EXPECT_THROW(PackPixels(*format, {4096}, 1, 1, bytes.data()), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
