#include "drivers/demosaic.h"

#include <opencv2/imgproc.hpp>

#include "basis/error.h"

namespace zbrdf {

int BayerToRgbConversionCode(PixelLayout layout) {
  // OpenCV names these aliases by the sensor's top-left 2x2 block (imgproc.hpp); the older
  // COLOR_BayerBG2RGB-style names count from the second row and are easy to get wrong.
  switch (layout) {
    case PixelLayout::kBayerRGGB:
      return cv::COLOR_BayerRGGB2RGB;
    case PixelLayout::kBayerGRBG:
      return cv::COLOR_BayerGRBG2RGB;
    case PixelLayout::kBayerGBRG:
      return cv::COLOR_BayerGBRG2RGB;
    case PixelLayout::kBayerBGGR:
      return cv::COLOR_BayerBGGR2RGB;
    case PixelLayout::kMono:
    case PixelLayout::kRgb:
      break;
  }
  throw InputError("demosaicing needs a Bayer frame, got layout '" + PixelLayoutName(layout) + "'");
}

cv::Mat DemosaicToRgb(const Frame& frame) {
  const size_t expected = static_cast<size_t>(frame.width) * static_cast<size_t>(frame.height) *
                          static_cast<size_t>(SamplesPerPixel(frame.layout));
  if (frame.width <= 0 || frame.height <= 0 || frame.data.size() != expected) {
    throw InputError("frame " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                     " (" + PixelLayoutName(frame.layout) + ") should hold " +
                     std::to_string(expected) + " samples, has " +
                     std::to_string(frame.data.size()));
  }
  // cvtColor does not modify its input; the const_cast only wraps the samples without a copy.
  uint16_t* samples = const_cast<uint16_t*>(frame.data.data());
  cv::Mat rgb16;
  switch (frame.layout) {
    case PixelLayout::kMono: {
      cv::Mat mono(frame.height, frame.width, CV_16UC1, samples);
      cv::cvtColor(mono, rgb16, cv::COLOR_GRAY2RGB);
      break;
    }
    case PixelLayout::kRgb:
      rgb16 = cv::Mat(frame.height, frame.width, CV_16UC3, samples);
      break;
    default: {
      if (frame.width < 2 || frame.height < 2) {
        throw InputError("a Bayer frame must be at least 2x2 to demosaic, got " +
                         std::to_string(frame.width) + "x" + std::to_string(frame.height));
      }
      cv::Mat raw(frame.height, frame.width, CV_16UC1, samples);
      cv::cvtColor(raw, rgb16, BayerToRgbConversionCode(frame.layout));
      break;
    }
  }
  cv::Mat rgb;
  rgb16.convertTo(rgb, CV_32FC3);
  return rgb;
}

}  // namespace zbrdf
