// The animated PNG writer against the APNG specification, read back by a parser written here:
// chunk layout and CRCs (a bitwise CRC-32, not zlib's table), frame count and delays, sequence
// numbers, and every frame's pixels (each frame's data rebuilt into a plain PNG and decoded by
// libspng, basis/png.h).
#include "pictures/animated_png.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "basis/error.h"
#include "basis/png.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

uint32_t Crc32(const std::string& bytes) {  // ISO 3309, reflected, polynomial 0xEDB88320
  uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char c : bytes) {
    crc ^= c;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

uint32_t U32(const std::string& s, size_t at) {
  return static_cast<uint32_t>(static_cast<uint8_t>(s[at])) << 24 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[at + 1])) << 16 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[at + 2])) << 8 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[at + 3]));
}

std::string Be32(uint32_t v) {
  return {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
          static_cast<char>(v)};
}

// The largest difference between a decoded RGB PNG and the BGR frame it was made from (-1 if
// their sizes or channel counts differ).
int MaxDifference(const PngImage& png, const cv::Mat& bgr) {
  if (png.width != bgr.cols || png.height != bgr.rows || png.channels != 3 ||
      bgr.type() != CV_8UC3) {
    return -1;
  }
  int worst = 0;
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(png.At(x, y, c) - bgr.at<cv::Vec3b>(y, x)[2 - c]));
      }
    }
  }
  return worst;
}

std::string Chunk(const std::string& type, const std::string& data) {
  return Be32(static_cast<uint32_t>(data.size())) + type + data + Be32(Crc32(type + data));
}

struct Parsed {
  std::string type, data;
};

std::vector<Parsed> Parse(const std::string& png) {
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  std::vector<Parsed> chunks;
  size_t at = 8;
  while (at < png.size()) {
    const uint32_t length = U32(png, at);
    const std::string type = png.substr(at + 4, 4), data = png.substr(at + 8, length);
    EXPECT_EQ(U32(png, at + 8 + length), Crc32(type + data)) << type << " CRC";
    chunks.push_back({type, data});
    at += 12 + length;
  }
  EXPECT_EQ(at, png.size());
  return chunks;
}

TEST(AnimatedPng, FramesDelaysAndPixelsReadBack) {
  std::vector<cv::Mat> frames;
  for (int f = 0; f < 5; ++f) {
    cv::Mat m(24, 40, CV_8UC3);
    for (int y = 0; y < m.rows; ++y) {
      for (int x = 0; x < m.cols; ++x) {
        m.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<uint8_t>(x * 6 + f),
                                          static_cast<uint8_t>(y * 10), static_cast<uint8_t>(f * 50));
      }
    }
    frames.push_back(m);
  }
  const std::string apng = EncodeAnimatedPng(frames, 12);
  const std::vector<Parsed> chunks = Parse(apng);
  ASSERT_GE(chunks.size(), 3u);
  EXPECT_EQ(chunks[0].type, "IHDR");
  EXPECT_EQ(U32(chunks[0].data, 0), 40u);
  EXPECT_EQ(U32(chunks[0].data, 4), 24u);
  ASSERT_EQ(chunks[1].type, "acTL");
  EXPECT_EQ(U32(chunks[1].data, 0), 5u);  // frames
  EXPECT_EQ(U32(chunks[1].data, 4), 0u);  // loop forever
  EXPECT_EQ(chunks.back().type, "IEND");
  // Walk the frames: fcTL, then IDAT (frame 0) or fdAT chunks; sequence numbers 0, 1, 2, ...
  uint32_t expected_sequence = 0;
  int frame = -1;
  std::vector<std::string> data(5);
  for (size_t k = 2; k + 1 < chunks.size(); ++k) {
    const Parsed& c = chunks[k];
    if (c.type == "fcTL") {
      ++frame;
      ASSERT_EQ(c.data.size(), 26u);
      EXPECT_EQ(U32(c.data, 0), expected_sequence++);
      EXPECT_EQ(U32(c.data, 4), 40u);
      EXPECT_EQ(U32(c.data, 8), 24u);
      EXPECT_EQ(U32(c.data, 12), 0u);
      EXPECT_EQ(U32(c.data, 16), 0u);
      EXPECT_EQ((static_cast<uint8_t>(c.data[20]) << 8) | static_cast<uint8_t>(c.data[21]), 1);
      EXPECT_EQ((static_cast<uint8_t>(c.data[22]) << 8) | static_cast<uint8_t>(c.data[23]), 12);
    } else if (c.type == "IDAT") {
      ASSERT_EQ(frame, 0) << "IDAT outside frame 0";
      data[0] += c.data;
    } else if (c.type == "fdAT") {
      ASSERT_GE(frame, 1);
      EXPECT_EQ(U32(c.data, 0), expected_sequence++);
      data[frame] += c.data.substr(4);
    } else {
      ADD_FAILURE() << "unexpected chunk " << c.type;
    }
  }
  ASSERT_EQ(frame, 4);
  // Each frame's data as a plain PNG decodes to the frame.
  for (int f = 0; f < 5; ++f) {
    const std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + Chunk("IHDR", chunks[0].data) +
                            Chunk("IDAT", data[f]) + Chunk("IEND", "");
    EXPECT_EQ(MaxDifference(DecodePng(png, "frame"), frames[f]), 0) << "frame " << f;
  }
  // A viewer without APNG support shows frame 0.
  EXPECT_EQ(MaxDifference(DecodePng(apng, "animation"), frames[0]), 0);
}

TEST(AnimatedPng, RejectsMismatchedFramesAndRates) {
  std::vector<cv::Mat> frames = {cv::Mat(8, 8, CV_8UC3, cv::Scalar(1, 2, 3)),
                                 cv::Mat(8, 9, CV_8UC3, cv::Scalar(1, 2, 3))};
  EXPECT_THROW(EncodeAnimatedPng(frames, 10), InputError);
  EXPECT_THROW(EncodeAnimatedPng({}, 10), InputError);
  frames.pop_back();
  EXPECT_THROW(EncodeAnimatedPng(frames, 0), InputError);
  EXPECT_NO_THROW(EncodeAnimatedPng(frames, 1));
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
