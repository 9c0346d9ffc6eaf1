#include "calibration/projector.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "basis/error.h"
#include "calibration/figures.h"
#include "rig/direction_maps.h"

namespace zbrdf {

namespace {

double Percentile(std::vector<float> v, double q) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

}  // namespace

std::vector<double> MonotoneInterpolate(const std::vector<int>& x, const std::vector<double>& y) {
  const size_t n = x.size();
  if (n < 2 || y.size() != n) throw InternalError("MonotoneInterpolate needs >= 2 points");
  std::vector<double> delta(n - 1), m(n);
  for (size_t i = 0; i + 1 < n; ++i) delta[i] = (y[i + 1] - y[i]) / (x[i + 1] - x[i]);
  m[0] = delta[0];
  m[n - 1] = delta[n - 2];
  for (size_t i = 1; i + 1 < n; ++i) m[i] = delta[i - 1] * delta[i] <= 0 ? 0 : 0.5 * (delta[i - 1] + delta[i]);
  // Fritsch-Carlson: limit the tangents so that each interval stays monotone.
  for (size_t i = 0; i + 1 < n; ++i) {
    if (delta[i] == 0) {
      m[i] = m[i + 1] = 0;
      continue;
    }
    const double a = m[i] / delta[i], b = m[i + 1] / delta[i];
    const double s = a * a + b * b;
    if (s > 9) {
      const double t = 3 / std::sqrt(s);
      m[i] = t * a * delta[i];
      m[i + 1] = t * b * delta[i];
    }
  }
  std::vector<double> out;
  for (size_t i = 0; i + 1 < n; ++i) {
    const double h = x[i + 1] - x[i];
    for (int xi = x[i]; xi < x[i + 1]; ++xi) {
      const double t = (xi - x[i]) / h;
      const double h00 = (1 + 2 * t) * (1 - t) * (1 - t), h10 = t * (1 - t) * (1 - t);
      const double h01 = t * t * (3 - 2 * t), h11 = t * t * (t - 1);
      out.push_back(h00 * y[i] + h10 * h * m[i] + h01 * y[i + 1] + h11 * h * m[i + 1]);
    }
  }
  out.push_back(y.back());
  // Rounding can leave a hair of decrease where the curve is flat: keep it exactly monotone.
  for (size_t i = 1; i < out.size(); ++i) out[i] = std::max(out[i], out[i - 1]);
  return out;
}

ProjectorCalibrationResult CalibrateProjector(CalibrationRig& rig, const RigCalibration& c,
                                              Correspondences correspondences) {
  ProjectorCalibrationResult result;
  const int max_level = (1 << c.projector_bit_depth) - 1;
  const int step = std::max(1, (max_level + 1) / 32);
  for (int level = 0; level < max_level; level += step) result.levels.push_back(level);
  result.levels.push_back(max_level);
  const long total = static_cast<long>(result.levels.size()) + 2 + (correspondences.count ? 0 : 1);
  long done = 0;

  // --- Response, on the white target.
  rig.place_target(Target::kWhite);
  const double t = MeterWhite(rig, c);
  const std::vector<double> bracket = {t, 4 * t, 16 * t};
  std::vector<HdrImage> images;
  for (int level : result.levels) {
    ShowPattern(rig, UniformPattern(c, level));
    images.push_back(TakeHdr(rig, c, bracket, "white target at projector level " + std::to_string(level)));
    Report(rig.progress, {"projector", ++done, total, "patterns"});
  }
  const size_t pixels = images[0].rate.size();
  std::vector<uint8_t> use(pixels, 0);
  for (size_t i = 0; i < pixels; ++i) {
    use[i] = c.CameraValid(static_cast<int>(i)) && images.front().valid[i] && images.back().valid[i];
  }
  auto sum_above_dark = [&](const HdrImage& image) {
    double sum = 0;
    for (size_t i = 0; i < pixels; ++i) {
      if (use[i] && image.valid[i]) sum += image.rate[i] - images.front().rate[i];
    }
    return sum;
  };
  const double full = sum_above_dark(images.back());
  if (!(full > 0)) throw DeviceError("projector calibration: full white is no brighter than black; is the projector on?");
  double dark_sum = 0;
  for (size_t i = 0; i < pixels; ++i) {
    if (use[i]) dark_sum += images.front().rate[i];
  }
  for (size_t k = 0; k < images.size(); ++k) result.measured.push_back(sum_above_dark(images[k]) / full);
  std::vector<double> monotone = result.measured;
  monotone.front() = 0;
  monotone.back() = 1;
  for (size_t k = 1; k < monotone.size(); ++k) monotone[k] = std::clamp(monotone[k], monotone[k - 1], 1.0);
  result.response.response = MonotoneInterpolate(result.levels, monotone);
  result.response.black_fraction = std::max(0.0, dark_sum / full);

  // --- Camera flat field: the white target looks the same from every camera pixel.
  result.camera_flat.width = c.camera_width;
  result.camera_flat.height = c.camera_height;
  result.camera_flat.value.assign(pixels, 0.0f);
  for (int ch = -1; ch < 3; ++ch) {
    std::vector<float> ratios;
    for (int y = 0; y < c.camera_height; ++y) {
      for (int x = 0; x < c.camera_width; ++x) {
        const size_t i = static_cast<size_t>(y) * c.camera_width + x;
        if (!use[i] || BayerChannel(c.layout, x, y) != ch) continue;
        const float ratio = static_cast<float>((images.back().rate[i] - images.front().rate[i]) / c.camera_response[i]);
        result.camera_flat.value[i] = ratio;
        ratios.push_back(ratio);
      }
    }
    const double median = Percentile(ratios, 0.5);
    if (!(median > 0)) continue;
    for (int y = 0; y < c.camera_height; ++y) {
      for (int x = 0; x < c.camera_width; ++x) {
        const size_t i = static_cast<size_t>(y) * c.camera_width + x;
        if (use[i] && BayerChannel(c.layout, x, y) == ch) {
          result.camera_flat.value[i] = static_cast<float>(std::max(0.0, result.camera_flat.value[i] / median));
        }
      }
    }
  }
  // Pixels the calibration thinks valid but that saw nothing keep factor 1 (they are excluded
  // by their own zero signal elsewhere); invalid pixels stay 0 but have no response anyway.
  for (size_t i = 0; i < pixels; ++i) {
    if (!use[i] && c.CameraValid(static_cast<int>(i))) result.camera_flat.value[i] = 1.0f;
  }

  // --- Projector flat field, through the mirror.
  rig.place_target(Target::kMirror);
  if (correspondences.count == 0) {
    correspondences = CaptureGrayCode(rig, c);
    Report(rig.progress, {"projector", ++done, total, "patterns"});
  }
  RigCalibration updated = c;
  updated.projector_response = result.response.response;
  const int mid = updated.LevelFor(0.5);
  const double tm = MeterWhite(rig, c);
  ShowPattern(rig, UniformPattern(c, mid));
  const HdrImage gray = TakeHdr(rig, c, {tm, 4 * tm}, "mirror at mid-gray");
  Report(rig.progress, {"projector", ++done, total, "patterns"});
  ShowPattern(rig, UniformPattern(c, 0));
  const HdrImage black = TakeHdr(rig, c, {tm, 4 * tm}, "mirror at black");
  Report(rig.progress, {"projector", ++done, total, "patterns"});
  const int pw = c.projector_width, ph = c.projector_height;
  cv::Mat sum(ph, pw, CV_32F, cv::Scalar(0)), count(ph, pw, CV_32F, cv::Scalar(0));
  for (size_t i = 0; i < pixels; ++i) {
    if (!correspondences.Has(static_cast<int>(i)) || !gray.valid[i] || !black.valid[i] ||
        !(c.camera_response[i] > 0) || !(result.camera_flat.value[i] > 0)) {
      continue;
    }
    const int u = static_cast<int>(correspondences.u[i]), v = static_cast<int>(correspondences.v[i]);
    if (u < 0 || v < 0 || u >= pw || v >= ph) continue;
    const double value = (gray.rate[i] - black.rate[i]) / (c.camera_response[i] * result.camera_flat.value[i]);
    sum.at<float>(v, u) += static_cast<float>(value);
    count.at<float>(v, u) += 1;
  }
  cv::Mat mean(ph, pw, CV_32F, cv::Scalar(0)), weight;
  cv::divide(sum, cv::max(count, 1e-6f), mean);
  cv::Mat seen = count > 0;
  seen.convertTo(weight, CV_32F, 1.0 / 255);
  cv::Mat blurred_value, blurred_weight;
  cv::GaussianBlur(mean.mul(weight), blurred_value, cv::Size(0, 0), 1.5);
  cv::GaussianBlur(weight, blurred_weight, cv::Size(0, 0), 1.5);
  result.projector_flat.width = pw;
  result.projector_flat.height = ph;
  result.projector_flat.value.assign(static_cast<size_t>(pw) * ph, std::nanf(""));
  std::vector<float> seen_values;
  int known = 0, lit_pixels = 0, lit_seen = 0;
  for (int y = 0; y < ph; ++y) {
    for (int x = 0; x < pw; ++x) {
      const size_t i = static_cast<size_t>(y) * pw + x;
      const float bw = blurred_weight.at<float>(y, x);
      if (bw > 0.05f) {
        result.projector_flat.value[i] = blurred_value.at<float>(y, x) / bw;
        ++known;
      }
      if (c.ProjectorValid(static_cast<int>(i))) {
        ++lit_pixels;
        lit_seen += count.at<float>(y, x) > 0;
      }
      if (count.at<float>(y, x) > 0) seen_values.push_back(result.projector_flat.value[i]);
    }
  }
  if (known < 16) {
    throw DeviceError("projector flat field: the mirror image shows only " + std::to_string(known) +
                      " projector pixels; is the mirror target in place?");
  }
  // Fill the rest from the nearest known pixel (they light nothing the camera sees).
  {
    cv::Mat unknown(ph, pw, CV_8U, cv::Scalar(0));
    for (int y = 0; y < ph; ++y) {
      for (int x = 0; x < pw; ++x) unknown.at<uint8_t>(y, x) = std::isnan(result.projector_flat.value[static_cast<size_t>(y) * pw + x]) ? 255 : 0;
    }
    cv::Mat distance, labels;
    cv::distanceTransform(unknown, distance, labels, cv::DIST_L2, cv::DIST_MASK_5, cv::DIST_LABEL_PIXEL);
    std::vector<float> by_label(static_cast<size_t>(pw) * ph + 1, 1.0f);
    for (int y = 0; y < ph; ++y) {
      for (int x = 0; x < pw; ++x) {
        if (!unknown.at<uint8_t>(y, x)) by_label[labels.at<int>(y, x)] = result.projector_flat.value[static_cast<size_t>(y) * pw + x];
      }
    }
    for (int y = 0; y < ph; ++y) {
      for (int x = 0; x < pw; ++x) {
        if (unknown.at<uint8_t>(y, x)) result.projector_flat.value[static_cast<size_t>(y) * pw + x] = by_label[labels.at<int>(y, x)];
      }
    }
  }
  const double top = Percentile(seen_values, 0.995);
  if (!(top > 0)) throw DeviceError("projector flat field: no light through the mirror");
  for (float& v : result.projector_flat.value) v = static_cast<float>(v / top);

  // --- Report.
  double sxy = 0, sxx = 0;  // gamma: log r = gamma log u over the measured levels with r > 1%
  for (size_t k = 1; k + 1 < result.levels.size(); ++k) {
    if (result.measured[k] <= 0.01) continue;
    const double lx = std::log(static_cast<double>(result.levels[k]) / max_level), ly = std::log(result.measured[k]);
    sxy += lx * ly;
    sxx += lx * lx;
  }
  std::vector<float> flat_seen;
  result.projector_seen.assign(result.projector_flat.value.size(), 0);
  for (size_t i = 0; i < result.projector_flat.value.size(); ++i) {
    if (count.at<float>(static_cast<int>(i / pw), static_cast<int>(i % pw)) > 0) {
      flat_seen.push_back(result.projector_flat.value[i]);
      result.projector_seen[i] = 1;
    }
  }
  std::vector<float> camera_values;
  for (size_t i = 0; i < pixels; ++i) {
    if (use[i]) camera_values.push_back(result.camera_flat.value[i]);
  }
  result.report = {{"levels", result.levels},
                   {"measured_response", result.measured},
                   {"gamma_fit", sxx > 0 ? sxy / sxx : 0.0},
                   {"black_fraction", result.response.black_fraction},
                   {"mid_gray_level", mid},
                   {"projector_flat", {{"min", Percentile(flat_seen, 0.0)},
                                       {"p5", Percentile(flat_seen, 0.05)},
                                       {"median", Percentile(flat_seen, 0.5)},
                                       {"lit_pixels_seen_fraction", lit_pixels ? double(lit_seen) / lit_pixels : 0.0}}},
                   {"camera_flat", {{"p5", Percentile(camera_values, 0.05)},
                                    {"p95", Percentile(camera_values, 0.95)}}},
                   {"correspondences", correspondences.count}};
  return result;
}

void WriteProjectorFigures(const std::string& folder, const ProjectorCalibrationResult& result) {
  const int max_level = static_cast<int>(result.response.response.size()) - 1;
  PlotSeries measured{"measured", {}, result.measured, PlotStyle::kPoints};
  for (int level : result.levels) measured.x.push_back(level);
  PlotSeries table{"interpolated response (monotone cubic)", {}, result.response.response, PlotStyle::kLine};
  for (int level = 0; level <= max_level; ++level) table.x.push_back(level);
  char title[160];
  std::snprintf(title, sizeof(title), "projector response (fitted gamma %.3g, black %.3g%%)",
                result.report.value("gamma_fit", 0.0), 100 * result.response.black_fraction);
  WritePlot(folder + "/projector_response.png", title, "level", "normalized output", {measured, table});
  std::vector<float> shown = result.projector_flat.value;
  double lo = 1;
  for (size_t i = 0; i < shown.size(); ++i) {
    if (result.projector_seen[i]) lo = std::min<double>(lo, shown[i]);
    else shown[i] = std::nanf("");  // filled from neighbours: black in the picture
  }
  WriteFieldImage(folder + "/projector_flat.png",
                  "projector flat field through the mirror (black: not seen, filled in)",
                  result.projector_flat.width, result.projector_flat.height, shown,
                  std::floor(lo * 20) / 20, 1.02);
}

}  // namespace zbrdf
