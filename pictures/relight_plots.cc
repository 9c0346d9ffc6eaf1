#include "pictures/relight_plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "basis/error.h"
#include "pictures/plot_style.h"

namespace zbrdf {
namespace {

using plot::Text;

bool Usable(const std::pair<double, double>& p) {
  return std::isfinite(p.first) && std::isfinite(p.second) && p.first > 0 && p.second > 0;
}

}  // namespace

cv::Mat DrawLogLogPanel(const std::string& title, const std::string& x_label,
                        const std::string& y_label, const std::vector<XySeries>& series) {
  const int w = 640, h = 430, left = 70, right = 150, top = 44, bottom = 48;
  cv::Mat image(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  double lx0 = std::numeric_limits<double>::infinity(), lx1 = -lx0, ly0 = lx0, ly1 = -lx0;
  for (const XySeries& s : series) {
    for (const auto& p : s.points) {
      if (!Usable(p)) continue;
      lx0 = std::min(lx0, std::log10(p.first));
      lx1 = std::max(lx1, std::log10(p.first));
      ly0 = std::min(ly0, std::log10(p.second));
      ly1 = std::max(ly1, std::log10(p.second));
    }
  }
  Text(image, title, cv::Point(10, 22), 0.5);
  if (!std::isfinite(lx0)) {
    Text(image, "no data", cv::Point(w / 2 - 30, h / 2));
    return image;
  }
  // Pad to at least a tenth of a decade on each side.
  lx0 = std::floor(lx0 * 10 - 1) / 10;
  lx1 = std::ceil(lx1 * 10 + 1) / 10;
  ly0 = std::floor(ly0 * 10 - 1) / 10;
  ly1 = std::ceil(ly1 * 10 + 1) / 10;
  const int x0 = left, x1 = w - right, y0 = top, y1 = h - bottom;
  auto X = [&](double v) {
    return x0 + static_cast<int>((std::log10(v) - lx0) / (lx1 - lx0) * (x1 - x0));
  };
  auto Y = [&](double v) {
    return y1 - static_cast<int>((std::log10(v) - ly0) / (ly1 - ly0) * (y1 - y0));
  };
  cv::rectangle(image, cv::Point(x0, y0), cv::Point(x1, y1), cv::Scalar(200, 200, 200));
  auto ticks = [](double lo, double hi) {
    std::vector<double> t;
    for (int e = static_cast<int>(std::floor(lo)); e <= static_cast<int>(std::ceil(hi)); ++e) {
      for (double m : {1.0, 2.0, 5.0}) {
        const double v = m * std::pow(10.0, e);
        if (std::log10(v) >= lo && std::log10(v) <= hi) t.push_back(v);
      }
    }
    return t;
  };
  for (double v : ticks(lx0, lx1)) {
    cv::line(image, cv::Point(X(v), y0), cv::Point(X(v), y1), cv::Scalar(235, 235, 235));
    char b[24];
    std::snprintf(b, sizeof(b), "%g", v);
    Text(image, b, cv::Point(X(v) - 12, y1 + 16));
  }
  for (double v : ticks(ly0, ly1)) {
    cv::line(image, cv::Point(x0, Y(v)), cv::Point(x1, Y(v)), cv::Scalar(235, 235, 235));
    char b[24];
    std::snprintf(b, sizeof(b), "%g", v);
    Text(image, b, cv::Point(6, Y(v) + 4));
  }
  Text(image, x_label, cv::Point(x0 + 80, h - 12));
  Text(image, y_label, cv::Point(x0 + 4, y0 - 5));
  for (size_t s = 0; s < series.size(); ++s) {
    const cv::Scalar color = plot::SeriesColor(s);
    std::vector<std::pair<double, double>> pts;
    for (const auto& p : series[s].points) {
      if (Usable(p)) pts.push_back(p);
    }
    std::sort(pts.begin(), pts.end());
    for (size_t k = 0; k < pts.size(); ++k) {
      const cv::Point at(X(pts[k].first), Y(pts[k].second));
      cv::circle(image, at, 3, color, cv::FILLED, cv::LINE_AA);
      if (k > 0) {
        cv::line(image, cv::Point(X(pts[k - 1].first), Y(pts[k - 1].second)), at, color, 2,
                 cv::LINE_AA);
      }
    }
    const int ly = y0 + 12 + 20 * static_cast<int>(s);
    cv::line(image, cv::Point(x1 + 12, ly - 4), cv::Point(x1 + 32, ly - 4), color, 2, cv::LINE_AA);
    Text(image, series[s].name, cv::Point(x1 + 38, ly));
  }
  return image;
}

cv::Mat LabeledStrip(const std::vector<cv::Mat>& images, const std::vector<std::string>& labels) {
  ZBRDF_ASSERT(!images.empty() && images.size() == labels.size(), "LabeledStrip: bad input");
  std::vector<cv::Mat> tiles;
  for (size_t k = 0; k < images.size(); ++k) {
    ZBRDF_ASSERT(images[k].rows == images[0].rows && images[k].type() == CV_8UC3,
                 "LabeledStrip: images differ in height or type");
    // Small images are enlarged (nearest neighbour, whole factors) to at least 160 pixels wide, so
    // that the label fits and the noise stays visible.
    cv::Mat image = images[k];
    const int factor = std::max(1, (160 + image.cols - 1) / image.cols);
    if (factor > 1) cv::resize(image, image, cv::Size(), factor, factor, cv::INTER_NEAREST);
    cv::Mat tile;
    cv::copyMakeBorder(image, tile, 22, 0, 0, 2, cv::BORDER_CONSTANT, cv::Scalar(30, 30, 30));
    Text(tile, labels[k], cv::Point(4, 15), 0.42, cv::Scalar(235, 235, 235));
    tiles.push_back(tile);
  }
  cv::Mat strip;
  cv::hconcat(tiles, strip);
  return strip;
}

}  // namespace zbrdf
