#include "pictures/accuracy_plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "pictures/image.h"
#include "pictures/plot_style.h"

namespace zbrdf {
using plot::Text;

void WriteErrorCdfPlot(const std::string& path, const std::string& title,
                       const std::vector<PlotSeries>& series) {
  const int w = 900, h = 480, left = 60, right = 300, top = 36, bottom = 50;
  const double x_max = 1.5;
  cv::Mat image(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  const int x0 = left, x1 = w - right, y0 = top, y1 = h - bottom;
  auto X = [&](double e) { return x0 + static_cast<int>(std::min(e, x_max) / x_max * (x1 - x0)); };
  auto Y = [&](double f) { return y1 - static_cast<int>(f * (y1 - y0)); };
  Text(image, title, cv::Point(10, 22), 0.5);
  cv::rectangle(image, cv::Point(x0, y0), cv::Point(x1, y1), cv::Scalar(200, 200, 200));
  for (double e = 0; e <= x_max + 1e-9; e += 0.25) {
    cv::line(image, cv::Point(X(e), y0), cv::Point(X(e), y1), cv::Scalar(235, 235, 235));
    char b[16];
    std::snprintf(b, sizeof(b), "%.2f", e);
    Text(image, b, cv::Point(X(e) - 14, y1 + 16));
  }
  for (double f = 0; f <= 1.0 + 1e-9; f += 0.25) {
    cv::line(image, cv::Point(x0, Y(f)), cv::Point(x1, Y(f)), cv::Scalar(235, 235, 235));
    char b[16];
    std::snprintf(b, sizeof(b), "%.2f", f);
    Text(image, b, cv::Point(8, Y(f) + 4));
  }
  Text(image, "cosine-weighted L2 error (relative)", cv::Point(x0 + 120, h - 12));
  for (size_t s = 0; s < series.size(); ++s) {
    std::vector<double> v;
    for (double e : series[s].values) {
      if (std::isfinite(e)) v.push_back(e);
    }
    if (v.empty()) continue;
    std::sort(v.begin(), v.end());
    const cv::Scalar color = plot::SeriesColor(s);
    std::vector<cv::Point> pts{cv::Point(X(0), Y(0))};
    for (size_t k = 0; k < v.size(); ++k) {
      pts.emplace_back(X(v[k]), Y(static_cast<double>(k) / v.size()));
      pts.emplace_back(X(v[k]), Y(static_cast<double>(k + 1) / v.size()));
    }
    cv::polylines(image, pts, false, color, 2, cv::LINE_AA);
    const double median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
    cv::circle(image, cv::Point(X(median), Y(0.5)), 4, color, cv::FILLED, cv::LINE_AA);
    char b[96];
    std::snprintf(b, sizeof(b), "%s: median %.3f", series[s].name.c_str(), median);
    cv::line(image, cv::Point(x1 + 10, y0 + 12 + 22 * static_cast<int>(s)),
             cv::Point(x1 + 30, y0 + 12 + 22 * static_cast<int>(s)), color, 2);
    Text(image, b, cv::Point(x1 + 34, y0 + 16 + 22 * static_cast<int>(s)), 0.38);
  }
  WritePng(path, image);
}

void WriteErrorBarPlot(const std::string& path, const std::string& title,
                       const std::vector<BarItem>& items) {
  std::vector<BarItem> sorted = items;
  std::sort(sorted.begin(), sorted.end(), [](const BarItem& a, const BarItem& b) {
    const double va = std::isfinite(a.value) ? a.value : 1e9, vb = std::isfinite(b.value) ? b.value : 1e9;
    return va < vb;
  });
  const int n = std::max<int>(1, static_cast<int>(sorted.size()));
  const int left = 50, top = 36, bottom = 150, right = 20;
  const int bar = std::clamp((600 - left - right) / n, 9, 24);  // few items: wider bars
  const int w = std::max(600, left + right + bar * n), h = 480;
  const bool baselines = std::any_of(sorted.begin(), sorted.end(),
                                     [](const BarItem& b) { return std::isfinite(b.baseline); });
  const double y_max = 2.0;
  cv::Mat image(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  const int y0 = top, y1 = h - bottom;
  auto Y = [&](double e) { return y1 - static_cast<int>(std::clamp(e, 0.0, y_max) / y_max * (y1 - y0)); };
  Text(image, title + (baselines ? "  (black ticks: Ngan et al. 2005, dense data)" : ""),
       cv::Point(10, 22), 0.45);
  for (double e = 0; e <= y_max + 1e-9; e += 0.5) {
    cv::line(image, cv::Point(left, Y(e)), cv::Point(w - right, Y(e)),
             e == 1.0 ? cv::Scalar(160, 160, 220) : cv::Scalar(230, 230, 230));
    char b[16];
    std::snprintf(b, sizeof(b), "%.1f", e);
    Text(image, b, cv::Point(10, Y(e) + 4));
  }
  for (size_t k = 0; k < sorted.size(); ++k) {
    const int x = left + bar * static_cast<int>(k);
    if (std::isfinite(sorted[k].value)) {
      cv::rectangle(image, cv::Point(x + 1, Y(sorted[k].value)), cv::Point(x + bar - 2, y1),
                    sorted[k].value > 1.0 ? cv::Scalar(60, 60, 220) : cv::Scalar(180, 120, 40),
                    cv::FILLED);
    }
    if (std::isfinite(sorted[k].baseline)) {
      cv::line(image, cv::Point(x, Y(sorted[k].baseline)), cv::Point(x + bar - 1, Y(sorted[k].baseline)),
               cv::Scalar(0, 0, 0), 2);
    }
    // Rotated labels: draw the name vertically, one character per line is unreadable, so write
    // it into a small image and rotate.
    cv::Mat label(12, bottom - 8, CV_8UC3, cv::Scalar(255, 255, 255));
    cv::putText(label, sorted[k].name.substr(0, 28), cv::Point(0, 10), cv::FONT_HERSHEY_SIMPLEX, 0.32,
                cv::Scalar(40, 40, 40), 1, cv::LINE_AA);
    cv::Mat rotated;
    cv::rotate(label, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
    if (x + rotated.cols <= w && y1 + 4 + rotated.rows <= h) {
      rotated.copyTo(image(cv::Rect(x - 2, y1 + 4, rotated.cols, rotated.rows)));
    }
  }
  WritePng(path, image);
}

}  // namespace zbrdf
