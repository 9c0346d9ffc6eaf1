// Pictures of the relighting benchmark (tools/relight_bench.h): error against time on log-log
// axes, and frames side by side with labels.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

namespace zbrdf {

struct XySeries {
  std::string name;
  std::vector<std::pair<double, double>> points;  // (x, y), both > 0; others are left out
};
// One panel: the series as lines with markers on log10 axes spanning their points (whole
// decades and 2x, 5x ticks), a legend at the right.
cv::Mat DrawLogLogPanel(const std::string& title, const std::string& x_label,
                        const std::string& y_label, const std::vector<XySeries>& series);

// Images of equal height side by side, each with its label drawn on a dark band at the top;
// images narrower than 160 pixels are enlarged by a whole factor (nearest neighbour).
cv::Mat LabeledStrip(const std::vector<cv::Mat>& images, const std::vector<std::string>& labels);

}  // namespace zbrdf
