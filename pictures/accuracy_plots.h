// Plots of the accuracy benchmark (tools/accuracy.h): error CDFs per method and per-material bars.
#pragma once

#include <string>
#include <vector>

namespace zbrdf {

struct PlotSeries {
  std::string name;
  std::vector<double> values;  // non-finite values are left out
};
// The empirical CDF of each series' values (cosine-weighted L2 errors), x from 0 to 1.5 (values
// beyond are counted but drawn at the right edge), one colour per series with a legend and the
// median marked. Throws InputError naming the file if it cannot be written.
void WriteErrorCdfPlot(const std::string& path, const std::string& title,
                       const std::vector<PlotSeries>& series);

struct BarItem {
  std::string name;
  double value = 0;     // the method's error
  double baseline = 0;  // a reference error drawn beside it (NaN: none)
};
// One bar per item, sorted by value, with the baseline as a tick; values clipped at 2.
void WriteErrorBarPlot(const std::string& path, const std::string& title,
                       const std::vector<BarItem>& items);

}  // namespace zbrdf
