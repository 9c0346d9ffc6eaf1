// Figures for the calibration reports, drawn with OpenCV: x-y plots, grouped bar charts and
// false-colour pictures of per-pixel fields. PNGs, written atomically.
#pragma once

#include <string>
#include <vector>

namespace zbrdf {

enum class PlotStyle { kPoints, kLine };

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
  PlotStyle style = PlotStyle::kLine;
};

// Linear axes spanning all series (with zero included when the data are non-negative).
void WritePlot(const std::string& path, const std::string& title, const std::string& x_label,
               const std::string& y_label, const std::vector<PlotSeries>& series);

// Groups of bars: groups[g] is labelled group_labels[g]; each group has one bar per entry of
// bar_labels, heights values[g][b] (may be negative).
void WriteBarChart(const std::string& path, const std::string& title,
                   const std::vector<std::string>& group_labels,
                   const std::vector<std::string>& bar_labels,
                   const std::vector<std::vector<double>>& values);

// A field (width x height, row-major) in false colour between lo and hi; NaN is black. A
// colour bar with the range is drawn beside it.
void WriteFieldImage(const std::string& path, const std::string& title, int width, int height,
                     const std::vector<float>& values, double lo, double hi);

}  // namespace zbrdf
