#include "pictures/brdf_plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "acquisition/zonal.h"
#include "basis/spherical_harmonics.h"
#include "basis/target_basis.h"
#include "brdf/sh_file.h"

namespace zbrdf {
namespace {

const cv::Scalar kChannelColor[3] = {cv::Scalar(40, 40, 220), cv::Scalar(40, 170, 40),
                                     cv::Scalar(220, 90, 30)};  // BGR for R, G, B
const cv::Scalar kGrid(215, 215, 215), kText(40, 40, 40), kWhite(255, 255, 255);

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

void PutLabel(cv::Mat& image, const std::string& text, cv::Point at, double scale = 0.45,
              cv::Scalar color = kText) {
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, color, 1, cv::LINE_AA);
}

cv::Mat PolarPanel(const IncidenceSlice& slice, bool log_scale) {
  constexpr int kWidth = 380, kHeight = 240, kRadius = 165;
  cv::Mat panel(kHeight, kWidth, CV_8UC3, kWhite);
  const cv::Point2d center(kWidth / 2.0, kHeight - 28.0);
  auto at = [&](double theta_o_rad, double r) {
    return cv::Point(static_cast<int>(std::lround(center.x + r * kRadius * std::sin(theta_o_rad))),
                     static_cast<int>(std::lround(center.y - r * kRadius * std::cos(theta_o_rad))));
  };
  for (double r : {0.25, 0.5, 0.75, 1.0}) {
    cv::ellipse(panel, center,
                cv::Size(static_cast<int>(r * kRadius), static_cast<int>(r * kRadius)), 0, 180, 360,
                kGrid, 1, cv::LINE_AA);
  }
  for (int deg = -90; deg <= 90; deg += 30) {
    cv::line(panel, at(0, 0), at(deg * M_PI / 180, 1.0), kGrid, 1, cv::LINE_AA);
  }
  double f_max = 0;
  for (const Rgb& f : slice.f) f_max = std::max(f_max, f.Max());
  const double theta_i = slice.theta_i_deg * M_PI / 180;
  // Incident direction (light) and its mirror direction.
  cv::arrowedLine(panel, at(theta_i, 1.05), at(theta_i, 0.12), cv::Scalar(0, 140, 255), 2,
                  cv::LINE_AA, 0, 0.08);
  cv::line(panel, at(0, 0), at(-theta_i, 1.0), cv::Scalar(150, 150, 150), 1, cv::LINE_4);
  if (f_max > 0) {
    for (int c = 0; c < 3; ++c) {
      std::vector<cv::Point> points;
      for (size_t k = 0; k < slice.f.size(); ++k) {
        double r = slice.f[k][c] / f_max;
        if (log_scale) {
          r = slice.f[k][c] > 0
                  ? std::clamp(std::log10(slice.f[k][c] / f_max) / 4.0 + 1.0, 0.0, 1.0)
                  : 0.0;
        }
        points.push_back(at(slice.theta_o_deg[k] * M_PI / 180, std::max(0.0, r)));
      }
      cv::polylines(panel, points, false, kChannelColor[c], 2, cv::LINE_AA);
    }
  }
  PutLabel(panel, Format("theta_i = %.0f deg", slice.theta_i_deg), cv::Point(8, 18), 0.5);
  PutLabel(panel,
           log_scale ? Format("log10, 4 decades below %.3g /sr", f_max)
                     : Format("max f_r = %.4g /sr", f_max),
           cv::Point(8, 38), 0.42);
  PutLabel(panel, "-90", cv::Point(6, kHeight - 10), 0.4);
  PutLabel(panel, "+90 deg", cv::Point(kWidth - 62, kHeight - 10), 0.4);
  PutLabel(panel, "light", at(theta_i, 1.1) + cv::Point(-10, -4), 0.4, cv::Scalar(0, 110, 220));
  return panel;
}

void AddEnergy(const Eigen::MatrixXd& m, const std::vector<int>& degree_row,
               const std::vector<int>& degree_col, int channel, BandEnergy* out) {
  for (int a = 0; a < m.rows(); ++a) {
    for (int b = 0; b < m.cols(); ++b) {
      const double e = m(a, b) * m(a, b);
      out->by_l_in[degree_row[a]][channel] += e;
      out->by_l_out[degree_col[b]][channel] += e;
    }
  }
}

BandEnergy EnergyOf(const std::string& label, const std::array<Eigen::MatrixXd, 3>& m,
                    const std::vector<int>& degree_row, const std::vector<int>& degree_col) {
  BandEnergy e;
  e.label = label;
  int max_l = 0;
  for (int l : degree_row) max_l = std::max(max_l, l);
  for (int l : degree_col) max_l = std::max(max_l, l);
  e.by_l_in.assign(max_l + 1, {0, 0, 0});
  e.by_l_out.assign(max_l + 1, {0, 0, 0});
  for (int c = 0; c < 3; ++c) AddEnergy(m[c], degree_row, degree_col, c, &e);
  return e;
}

cv::Mat EnergyChart(const std::vector<std::array<double, 3>>& values, const std::string& caption) {
  const int groups = static_cast<int>(values.size());
  const int left = 60, bar = 12, group = 3 * bar + 14, height = 260, top = 34, bottom = 40;
  int baseline = 0;
  const int caption_width =
      cv::getTextSize(caption, cv::FONT_HERSHEY_SIMPLEX, 0.5, 1, &baseline).width + 16;
  const int width = std::max({320, left + groups * group + 20, caption_width});
  cv::Mat chart(height, width, CV_8UC3, kWhite);
  double lo = 1e300, hi = 0;
  for (const auto& v : values) {
    for (double x : v) {
      if (x > 0) {
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
    }
  }
  PutLabel(chart, caption, cv::Point(8, 20), 0.5);
  if (!(hi > 0)) {
    PutLabel(chart, "no energy (all coefficients are 0)", cv::Point(left, height / 2));
    return chart;
  }
  const double decade_lo = std::floor(std::log10(lo)), decade_hi = std::ceil(std::log10(hi));
  const double span = std::max(1.0, decade_hi - decade_lo);
  const int plot_h = height - top - bottom;
  auto y_of = [&](double v) {
    const double t = (std::log10(v) - decade_lo) / span;
    return static_cast<int>(std::lround(top + plot_h * (1.0 - std::clamp(t, 0.0, 1.0))));
  };
  for (double d = decade_lo; d <= decade_hi; d += 1) {
    const int y = y_of(std::pow(10.0, d));
    cv::line(chart, cv::Point(left, y), cv::Point(width - 10, y), kGrid, 1);
    PutLabel(chart, Format("1e%.0f", d), cv::Point(6, y + 4), 0.4);
  }
  for (int l = 0; l < groups; ++l) {
    const int x0 = left + l * group + 7;
    for (int c = 0; c < 3; ++c) {
      if (values[l][c] <= 0) continue;
      cv::rectangle(chart, cv::Point(x0 + c * bar, y_of(values[l][c])),
                    cv::Point(x0 + (c + 1) * bar - 2, top + plot_h), kChannelColor[c], cv::FILLED);
    }
    PutLabel(chart, std::to_string(l), cv::Point(x0 + bar, height - bottom + 16), 0.45);
  }
  PutLabel(chart, "band l", cv::Point(width / 2 - 20, height - 6), 0.45);
  return chart;
}

cv::Mat StackVertically(const std::vector<cv::Mat>& parts) {
  int width = 0;
  for (const cv::Mat& m : parts) width = std::max(width, m.cols);
  std::vector<cv::Mat> padded;
  for (const cv::Mat& m : parts) {
    cv::Mat p;
    cv::copyMakeBorder(m, p, 0, 0, 0, width - m.cols, cv::BORDER_CONSTANT, kWhite);
    padded.push_back(p);
  }
  cv::Mat out;
  cv::vconcat(padded, out);
  return out;
}

}  // namespace

std::vector<IncidenceSlice> IncidencePlaneSlices(const Brdf& brdf,
                                                 const std::vector<double>& theta_i_deg,
                                                 int samples) {
  std::vector<IncidenceSlice> slices;
  for (double ti : theta_i_deg) {
    IncidenceSlice s;
    s.theta_i_deg = ti;
    const Vec3 w_i = SphericalDirection(ti * M_PI / 180, 0.0);
    std::vector<Vec3> w_is, w_os;
    for (int k = 0; k < samples; ++k) {
      // Open interval: the horizon itself is excluded.
      const double to = -90.0 + 180.0 * (k + 0.5) / samples;
      s.theta_o_deg.push_back(to);
      const double t = to * M_PI / 180;
      w_is.push_back(w_i);
      w_os.push_back({std::sin(t), 0.0, std::cos(t)});
    }
    s.f.resize(samples);
    brdf.EvalBatch(w_is, w_os, s.f);
    for (Rgb& f : s.f) {
      for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(f[c])) f[c] = 0;
      }
    }
    slices.push_back(std::move(s));
  }
  return slices;
}

cv::Mat DrawIncidenceSlices(const std::vector<IncidenceSlice>& slices, const std::string& title,
                            bool log_scale) {
  std::vector<cv::Mat> panels;
  for (const IncidenceSlice& s : slices) panels.push_back(PolarPanel(s, log_scale));
  cv::Mat row;
  cv::hconcat(panels, row);
  cv::Mat header(34, row.cols, CV_8UC3, kWhite);
  PutLabel(header, title, cv::Point(8, 22), 0.55);
  const int legend_x = std::max(8, row.cols - 250);
  for (int c = 0; c < 3; ++c) {
    cv::line(header, cv::Point(legend_x + 70 * c, 17), cv::Point(legend_x + 70 * c + 22, 17),
             kChannelColor[c], 2, cv::LINE_AA);
    PutLabel(header, c == 0 ? "R" : c == 1 ? "G" : "B", cv::Point(legend_x + 70 * c + 27, 22));
  }
  return StackVertically({header, row});
}

BandEnergy ZonalBandEnergy(const ZonalData& data) {
  std::vector<int> degree(data.tensor[0].rows());
  for (size_t k = 0; k < degree.size(); ++k) {
    int l, m;
    ShDegreeOrder(static_cast<int>(k), &l, &m);
    degree[k] = l;
  }
  std::vector<int> degree_col(data.tensor[0].cols());
  for (size_t k = 0; k < degree_col.size(); ++k) {
    int l, m;
    ShDegreeOrder(static_cast<int>(k), &l, &m);
    degree_col[k] = l;
  }
  return EnergyOf("zonal", data.tensor, degree, degree_col);
}

BandEnergy ShBandEnergy(const ShBrdfData& data) {
  const TargetBasis basis(data.target, data.order);
  std::vector<int> degree(basis.size());
  for (int k = 0; k < basis.size(); ++k) degree[k] = basis.degree(k);
  return EnergyOf(TargetName(data.target), data.coefficients, degree, degree);
}

cv::Mat DrawBandEnergy(const std::vector<BandEnergy>& energies, const std::string& title) {
  std::vector<cv::Mat> parts;
  int baseline = 0;
  cv::Mat header(30,
                 cv::getTextSize(title, cv::FONT_HERSHEY_SIMPLEX, 0.55, 1, &baseline).width + 16,
                 CV_8UC3, kWhite);
  PutLabel(header, title, cv::Point(8, 21), 0.55);
  parts.push_back(header);
  for (const BandEnergy& e : energies) {
    // The two groupings side by side.
    cv::Mat in = EnergyChart(e.by_l_in, e.label + ": by band of the w_i function");
    cv::Mat out = EnergyChart(e.by_l_out, e.label + ": by band of the w_r function");
    const int height = std::max(in.rows, out.rows);
    cv::copyMakeBorder(in, in, 0, height - in.rows, 0, 0, cv::BORDER_CONSTANT, kWhite);
    cv::copyMakeBorder(out, out, 0, height - out.rows, 0, 0, cv::BORDER_CONSTANT, kWhite);
    cv::Mat row;
    cv::hconcat(std::vector<cv::Mat>{in, out}, row);
    parts.push_back(row);
  }
  return StackVertically(parts);
}

nlohmann::json SlicesJson(const std::vector<IncidenceSlice>& slices) {
  nlohmann::json j = nlohmann::json::array();
  for (const IncidenceSlice& s : slices) {
    nlohmann::json f = nlohmann::json::array();
    for (const Rgb& v : s.f) f.push_back({v.r, v.g, v.b});
    j.push_back({{"theta_i_deg", s.theta_i_deg}, {"theta_o_deg", s.theta_o_deg}, {"f_r", f}});
  }
  return j;
}

nlohmann::json BandEnergyJson(const BandEnergy& e) {
  auto rows = [](const std::vector<std::array<double, 3>>& v) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& x : v) j.push_back({x[0], x[1], x[2]});
    return j;
  };
  return {{"basis", e.label}, {"by_l_in", rows(e.by_l_in)}, {"by_l_out", rows(e.by_l_out)}};
}

}  // namespace zbrdf
