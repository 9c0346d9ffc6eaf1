// PNG files in memory (basis/png.h): files made by hand here (chunks, CRCs and zlib streams built
// with Python's zlib, independently of libspng) decode to their known samples; every kind zbrdf
// writes survives a round trip bit for bit; damaged and unsupported files are InputErrors.
#include "basis/png.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>

#include "basis/error.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// 3x2, 16-bit gray, rows unfiltered; samples 0x0102 0xfffe 7 / 256 1 65535 (big-endian in the
// file: a reader that forgets to swap them reads 0x0201 for the first).
const std::string kGray16(
    "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x03\x00\x00\x00"
    "\x02\x10\x00\x00\x00\x00\xe8\x8f\xe5\x85\x00\x00\x00\x16\x49\x44\x41\x54\x78\x9c\x63\x60\x64"
    "\xfa\xff\x8f\x81\x9d\x81\x91\x81\x81\xf1\xff\x7f\x00\x18\x52\x04\x08\xc7\x10\x2a\x6b\x00\x00"
    "\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82",
    79);

// 2x2, 8-bit RGB with a tEXt chunk: red, green / blue, (10, 20, 30).
const std::string kRgb8(
    "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x02\x00\x00\x00"
    "\x02\x08\x02\x00\x00\x00\xfd\xd4\x9a\x73\x00\x00\x00\x14\x74\x45\x58\x74\x43\x6f\x6d\x6d\x65"
    "\x6e\x74\x00\x6d\x61\x64\x65\x20\x62\x79\x20\x68\x61\x6e\x64\x2c\xa8\xfa\x29\x00\x00\x00\x13"
    "\x49\x44\x41\x54\x78\x9c\x63\xf8\xcf\xc0\xc0\x00\xc2\x0c\xff\xb9\x44\xe4\x00\x1a\x58\x03\x3a"
    "\x56\x63\xa2\x3c\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82",
    108);

// 1x1 palette image (colour type 3), valid.
const std::string kPalette(
    "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x01\x00\x00\x00"
    "\x01\x08\x03\x00\x00\x00\x28\xcb\x34\xbb\x00\x00\x00\x03\x50\x4c\x54\x45\x01\x02\x03\x0d\x87"
    "\x64\xd5\x00\x00\x00\x0a\x49\x44\x41\x54\x78\x9c\x63\x60\x00\x00\x00\x02\x00\x01\x48\xaf\xa4"
    "\x71\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82",
    82);

// A valid header declaring 100000 x 100000 16-bit RGBA pixels (80 GB) over 10 bytes of data.
const std::string kHuge(
    "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x01\x86\xa0\x00\x01\x86"
    "\xa0\x10\x06\x00\x00\x00\xf8\xc2\xd7\x8b\x00\x00\x00\x0b\x49\x44\x41\x54\x78\x9c\x63\x60\x80"
    "\x01\x00\x00\x0a\x00\x01\x7f\x80\x74\x5e\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82",
    68);

uint32_t Be32(const std::string& s, size_t at) {
  uint32_t v = 0;
  for (size_t k = 0; k < 4; ++k) v = v << 8 | static_cast<uint8_t>(s[at + k]);
  return v;
}

TEST(Png, DecodesFilesMadeByHand) {
  const PngImage gray = DecodePng(kGray16, "gray16");
  EXPECT_EQ(gray.width, 3);
  EXPECT_EQ(gray.height, 2);
  EXPECT_EQ(gray.channels, 1);
  EXPECT_EQ(gray.bit_depth, 16);
  EXPECT_EQ(gray.samples, (std::vector<uint16_t>{0x0102, 0xfffe, 7, 256, 1, 65535}));

  const PngImage rgb = DecodePng(kRgb8, "rgb8");
  EXPECT_EQ(rgb.channels, 3);
  EXPECT_EQ(rgb.bit_depth, 8);
  EXPECT_EQ(rgb.samples, (std::vector<uint16_t>{255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30}));
  EXPECT_EQ(rgb.At(1, 1, 2), 30);
}

TEST(Png, EveryKindRoundTripsBitForBitWithTheHeaderItDescribes) {
  constexpr int kColorTypes[5] = {0, 0, 4, 2, 6};
  std::mt19937 rng(17);
  for (int channels = 1; channels <= 4; ++channels) {
    for (const int bits : {8, 16}) {
      for (const int level : {-1, 0, 9}) {
        PngImage image(13, 7, channels, bits);
        for (uint16_t& v : image.samples)
          v = static_cast<uint16_t>(rng() % (bits == 8 ? 256 : 65536));
        const std::string png = EncodePng(image, level);
        // Signature, then IHDR: width, height, bit depth, colour type (0, 4, 2, 6 for 1-4
        // channels), deflate, adaptive filtering, no interlace.
        ASSERT_EQ(png.compare(0, 8, std::string("\x89PNG\r\n\x1a\n", 8)), 0);
        ASSERT_EQ(png.compare(12, 4, "IHDR"), 0);
        EXPECT_EQ(Be32(png, 16), 13u);
        EXPECT_EQ(Be32(png, 20), 7u);
        EXPECT_EQ(static_cast<uint8_t>(png[24]), bits);
        EXPECT_EQ(static_cast<uint8_t>(png[25]), kColorTypes[channels]);
        EXPECT_EQ(png.compare(png.size() - 12, 12, std::string("\0\0\0\0IEND\xae\x42\x60\x82", 12)),
                  0);
        const PngImage back = DecodePng(png, "round trip");
        EXPECT_EQ(back.width, 13);
        EXPECT_EQ(back.height, 7);
        EXPECT_EQ(back.channels, channels);
        EXPECT_EQ(back.bit_depth, bits);
        EXPECT_EQ(back.samples, image.samples) << channels << " channels, " << bits << " bits";
      }
    }
  }
}

TEST(Png, DamagedAndUnsupportedFilesAreInputErrorsNamingTheFile) {
  const auto message = [](const std::string& bytes) {
    try {
      DecodePng(bytes, "x/pattern.png");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  std::string bad_crc = kGray16;
  bad_crc[40] ^= 1;  // a byte of the IDAT's data: its CRC no longer matches
  for (const std::string& bytes :
       {std::string(), std::string("not a png"), kGray16.substr(0, 40), kGray16.substr(0, 60),
        kGray16.substr(0, kGray16.size() - 6), bad_crc, kPalette, kHuge}) {
    EXPECT_NE(message(bytes).find("x/pattern.png"), std::string::npos) << message(bytes);
  }
  EXPECT_NE(message(kPalette).find("colour type 3"), std::string::npos) << message(kPalette);
  EXPECT_NE(message(kHuge).find("100000x100000"), std::string::npos) << message(kHuge);
}

TEST(Png, ImpossibleImagesAreRefusedBeforeEncoding) {
  EXPECT_THROW(PngImage(0, 4, 1, 8), InputError);
  EXPECT_THROW(PngImage(4, 4, 5, 8), InputError);
  EXPECT_THROW(PngImage(4, 4, 1, 12), InputError);
  PngImage image(4, 4, 1, 8);
  image.samples[5] = 256;  // not an 8-bit sample: refused rather than wrapped to 0
  EXPECT_THROW(EncodePng(image), InputError);
  image.samples[5] = 255;
  EXPECT_THROW(EncodePng(image, 10), InputError);
  image.samples.pop_back();
  EXPECT_THROW(EncodePng(image), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
