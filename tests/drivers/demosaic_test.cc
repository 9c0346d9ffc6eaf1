#include "drivers/demosaic.h"

#include <gtest/gtest.h>

#include "basis/error.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// A mosaic of a uniform color: each site holds the channel its filter passes. The layout name
// gives the top-left 2x2 block row by row (RGGB: R at (0,0), G at (1,0) and (0,1), B at (1,1)).
Frame UniformMosaic(PixelLayout layout, uint16_t r, uint16_t g, uint16_t b, int w, int h) {
  const char* name = nullptr;
  switch (layout) {
    case PixelLayout::kBayerRGGB:
      name = "RGGB";
      break;
    case PixelLayout::kBayerGRBG:
      name = "GRBG";
      break;
    case PixelLayout::kBayerGBRG:
      name = "GBRG";
      break;
    case PixelLayout::kBayerBGGR:
      name = "BGGR";
      break;
    default:
      ADD_FAILURE();
      name = "RGGB";
  }
  Frame f;
  f.width = w;
  f.height = h;
  f.layout = layout;
  f.bit_depth = 16;
  f.data.resize(static_cast<size_t>(w * h));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const char c = name[(y % 2) * 2 + (x % 2)];
      f.data[static_cast<size_t>(y * w + x)] = c == 'R' ? r : (c == 'G' ? g : b);
    }
  }
  return f;
}

TEST(DemosaicTest, UniformColorComesBackInRgbOrderForEveryBayerLayout) {
  // Distinct, 16-bit-range values: a swapped channel or a wrong conversion code shows up.
  const uint16_t r = 40000, g = 1000, b = 12345;
  for (PixelLayout layout : {PixelLayout::kBayerRGGB, PixelLayout::kBayerGRBG,
                             PixelLayout::kBayerGBRG, PixelLayout::kBayerBGGR}) {
    const cv::Mat rgb = DemosaicToRgb(UniformMosaic(layout, r, g, b, 8, 6));
    ASSERT_EQ(rgb.type(), CV_32FC3);
    ASSERT_EQ(rgb.rows, 6);
    ASSERT_EQ(rgb.cols, 8);
    // Bilinear interpolation of a constant field is exact in the interior.
    for (int y = 1; y < 5; ++y) {
      for (int x = 1; x < 7; ++x) {
        const cv::Vec3f p = rgb.at<cv::Vec3f>(y, x);
        EXPECT_FLOAT_EQ(p[0], r) << PixelLayoutName(layout) << " at " << x << "," << y;
        EXPECT_FLOAT_EQ(p[1], g) << PixelLayoutName(layout) << " at " << x << "," << y;
        EXPECT_FLOAT_EQ(p[2], b) << PixelLayoutName(layout) << " at " << x << "," << y;
      }
    }
  }
}

TEST(DemosaicTest, MonoIsReplicatedAndRgbIsConverted) {
  Frame mono;
  mono.width = 2;
  mono.height = 1;
  mono.layout = PixelLayout::kMono;
  mono.data = {7, 4095};
  const cv::Mat m = DemosaicToRgb(mono);
  EXPECT_EQ(m.at<cv::Vec3f>(0, 1), cv::Vec3f(4095, 4095, 4095));
  Frame rgb;
  rgb.width = 1;
  rgb.height = 1;
  rgb.layout = PixelLayout::kRgb;
  rgb.data = {1, 2, 3};
  EXPECT_EQ(DemosaicToRgb(rgb).at<cv::Vec3f>(0, 0), cv::Vec3f(1, 2, 3));
}

TEST(DemosaicTest, RejectsFramesWhoseDataDoNotMatchTheirSize) {
  Frame f = UniformMosaic(PixelLayout::kBayerRGGB, 1, 2, 3, 4, 4);
  f.data.pop_back();
  EXPECT_THROW(DemosaicToRgb(f), InputError);
  EXPECT_THROW(BayerToRgbConversionCode(PixelLayout::kMono), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
