// The colours and text of the plots drawn with OpenCV (accuracy_plots.h, relight_plots.h).
// Internal to pictures/.
#pragma once

#include <opencv2/imgproc.hpp>
#include <string>

namespace zbrdf::plot {

// One colour per series, BGR, cycled.
inline cv::Scalar SeriesColor(size_t k) {
  static const cv::Scalar kColors[] = {cv::Scalar(180, 60, 20),  cv::Scalar(40, 140, 40),
                                       cv::Scalar(30, 30, 200),  cv::Scalar(0, 150, 220),
                                       cv::Scalar(150, 60, 150), cv::Scalar(90, 90, 90)};
  return kColors[k % std::size(kColors)];
}

inline void Text(cv::Mat& image, const std::string& s, cv::Point at, double scale = 0.42,
                 cv::Scalar color = cv::Scalar(40, 40, 40)) {
  cv::putText(image, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, color, 1, cv::LINE_AA);
}

}  // namespace zbrdf::plot
