#include "calibration/figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "drivers/bgr_png.h"

namespace zbrdf {

namespace {

// BGR: gray, red, green, blue (bar charts of an ideal value and R, G, B measurements).
const cv::Scalar kColors[] = {{140, 140, 140}, {40, 40, 220}, {40, 160, 40}, {200, 90, 30}};
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

void Save(const std::string& path, const cv::Mat& image) {
  WriteFileAtomically(path, EncodeBgrPng(image));
}

std::string Tick(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3g", v);
  return buf;
}

// Round step for about n ticks over span.
double NiceStep(double span, int n) {
  const double raw = span / n;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * p >= raw) return m * p;
  }
  return 10 * p;
}

struct Axes {
  double x0, x1, y0, y1;
  cv::Rect box;
  cv::Point Map(double x, double y) const {
    return {box.x + static_cast<int>(std::lround((x - x0) / (x1 - x0) * box.width)),
            box.y + box.height - static_cast<int>(std::lround((y - y0) / (y1 - y0) * box.height))};
  }
};

Axes DrawAxes(cv::Mat& img, double x0, double x1, double y0, double y1, const std::string& title,
              const std::string& x_label, const std::string& y_label, bool x_ticks = true) {
  Axes a{x0, x1, y0, y1, cv::Rect(90, 70, img.cols - 130, img.rows - 140)};
  cv::rectangle(img, a.box, cv::Scalar(0, 0, 0), 1);
  cv::putText(img, title, {10, 30}, kFont, title.size() > 80 ? 0.45 : 0.55, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  cv::putText(img, x_label, {a.box.x + a.box.width / 2 - 80, img.rows - 20}, kFont, 0.5,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, y_label, {5, a.box.y - 10}, kFont, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  const double ys = NiceStep(y1 - y0, 6);
  for (double y = std::ceil(y0 / ys) * ys; y <= y1 + 1e-9 * ys; y += ys) {
    const cv::Point p = a.Map(x0, y);
    cv::line(img, p, {a.box.x + a.box.width, p.y}, cv::Scalar(225, 225, 225), 1);
    cv::putText(img, Tick(std::abs(y) < 1e-12 * ys ? 0.0 : y), {5, p.y + 5}, kFont, 0.45,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  if (x_ticks) {
    const double xs = NiceStep(x1 - x0, 8);
    for (double x = std::ceil(x0 / xs) * xs; x <= x1 + 1e-9 * xs; x += xs) {
      const cv::Point p = a.Map(x, y0);
      cv::line(img, p, {p.x, a.box.y}, cv::Scalar(225, 225, 225), 1);
      cv::putText(img, Tick(std::abs(x) < 1e-12 * xs ? 0.0 : x), {p.x - 15, p.y + 20}, kFont, 0.45,
                  cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
  }
  cv::rectangle(img, a.box, cv::Scalar(0, 0, 0), 1);
  return a;
}

}  // namespace

void WritePlot(const std::string& path, const std::string& title, const std::string& x_label,
               const std::string& y_label, const std::vector<PlotSeries>& series) {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const PlotSeries& s : series) {
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x0 = std::min(x0, s.x[i]);
      x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.y[i]);
      y1 = std::max(y1, s.y[i]);
    }
  }
  if (!(x1 >= x0)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (x0 >= 0) x0 = 0;
  if (y0 >= 0) y0 = 0;
  if (x1 <= x0) x1 = x0 + 1;
  if (y1 <= y0) y1 = y0 + 1;
  y1 += 0.05 * (y1 - y0);
  cv::Mat img(520, 820, CV_8UC3, cv::Scalar(255, 255, 255));
  const Axes a = DrawAxes(img, x0, x1, y0, y1, title, x_label, y_label);
  for (size_t k = 0; k < series.size(); ++k) {
    const PlotSeries& s = series[k];
    const cv::Scalar color = kColors[k % 4];
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      const cv::Point p = a.Map(s.x[i], s.y[i]);
      if (s.style == PlotStyle::kPoints) {
        cv::circle(img, p, 4, color, cv::FILLED, cv::LINE_AA);
      } else if (i > 0) {
        cv::line(img, a.Map(s.x[i - 1], s.y[i - 1]), p, color, 2, cv::LINE_AA);
      }
    }
    const cv::Point legend{a.box.x + 15, a.box.y + 20 + 20 * static_cast<int>(k)};
    cv::rectangle(img, {legend.x, legend.y - 8}, {legend.x + 16, legend.y + 2}, color, cv::FILLED);
    cv::putText(img, s.label, {legend.x + 22, legend.y + 2}, kFont, 0.45, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
  }
  Save(path, img);
}

void WriteBarChart(const std::string& path, const std::string& title,
                   const std::vector<std::string>& group_labels,
                   const std::vector<std::string>& bar_labels,
                   const std::vector<std::vector<double>>& values) {
  double lo = 0, hi = 0;
  for (const auto& group : values) {
    for (double v : group) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (hi <= lo) hi = lo + 1;
  const double pad = 0.08 * (hi - lo);
  cv::Mat img(560, 1000, CV_8UC3, cv::Scalar(255, 255, 255));
  const Axes a = DrawAxes(img, 0, static_cast<double>(group_labels.size()), lo < 0 ? lo - pad : 0,
                          hi + pad, title, "", "", false);
  const cv::Point zero = a.Map(0, 0);
  cv::line(img, zero, {a.box.x + a.box.width, zero.y}, cv::Scalar(0, 0, 0), 1);
  const double group_width = 1.0, bar_width = 0.7 / std::max<size_t>(1, bar_labels.size());
  for (size_t g = 0; g < group_labels.size(); ++g) {
    for (size_t b = 0; b < bar_labels.size() && b < values[g].size(); ++b) {
      const double left = g * group_width + 0.15 + b * bar_width;
      const cv::Point p0 = a.Map(left, 0), p1 = a.Map(left + bar_width * 0.9, values[g][b]);
      cv::rectangle(img, cv::Point(p0.x, std::min(p0.y, p1.y)), cv::Point(p1.x, std::max(p0.y, p1.y)),
                    kColors[b % 4], cv::FILLED);
      cv::putText(img, Tick(values[g][b]), {p0.x, values[g][b] >= 0 ? p1.y - 5 : p1.y + 15}, kFont,
                  0.32, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
    const cv::Point label = a.Map(g * group_width + 0.35, a.y0);
    cv::putText(img, group_labels[g], {label.x, label.y + 22}, kFont, 0.5, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
  }
  for (size_t b = 0; b < bar_labels.size(); ++b) {
    const cv::Point legend{a.box.x + a.box.width - 250, a.box.y + 20 + 20 * static_cast<int>(b)};
    cv::rectangle(img, {legend.x, legend.y - 8}, {legend.x + 16, legend.y + 2}, kColors[b % 4], cv::FILLED);
    cv::putText(img, bar_labels[b], {legend.x + 22, legend.y + 2}, kFont, 0.45, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
  }
  Save(path, img);
}

void WriteFieldImage(const std::string& path, const std::string& title, int width, int height,
                     const std::vector<float>& values, double lo, double hi) {
  cv::Mat gray(height, width, CV_8UC1);
  cv::Mat mask(height, width, CV_8UC1);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const float v = values[static_cast<size_t>(y) * width + x];
      mask.at<uint8_t>(y, x) = std::isfinite(v) ? 255 : 0;
      const double t = std::isfinite(v) && hi > lo ? (v - lo) / (hi - lo) : 0;
      gray.at<uint8_t>(y, x) = static_cast<uint8_t>(std::clamp(t, 0.0, 1.0) * 255);
    }
  }
  cv::Mat color;
  cv::applyColorMap(gray, color, cv::COLORMAP_VIRIDIS);
  color.setTo(cv::Scalar(0, 0, 0), mask == 0);
  const double scale = std::min(3.0, 700.0 / std::max(width, height));
  cv::Mat big;
  cv::resize(color, big, cv::Size(), scale, scale, cv::INTER_NEAREST);
  cv::Mat img(big.rows + 90, big.cols + 140, CV_8UC3, cv::Scalar(255, 255, 255));
  big.copyTo(img(cv::Rect(10, 50, big.cols, big.rows)));
  cv::putText(img, title, {10, 30}, kFont, 0.55, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  // Colour bar.
  for (int i = 0; i < big.rows; ++i) {
    cv::Mat one(1, 1, CV_8UC1, cv::Scalar(255 - 255 * i / std::max(1, big.rows - 1)));
    cv::Mat c;
    cv::applyColorMap(one, c, cv::COLORMAP_VIRIDIS);
    cv::line(img, {big.cols + 30, 50 + i}, {big.cols + 50, 50 + i}, c.at<cv::Vec3b>(0, 0));
  }
  cv::putText(img, Tick(hi), {big.cols + 55, 58}, kFont, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, Tick(lo), {big.cols + 55, 50 + big.rows}, kFont, 0.45, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  Save(path, img);
}

}  // namespace zbrdf
