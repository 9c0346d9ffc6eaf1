#include "calibration/noise.h"

#include <algorithm>
#include <cmath>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "calibration/figures.h"

namespace zbrdf {

namespace {

struct PairStats {
  double mean = 0, variance = 0;
  size_t pixels = 0;
};

// Mean of (A + B) / 2 and var(A - B) / 2 over the selected pixels.
PairStats NoisePair(const Frame& a, const Frame& b, const std::vector<uint8_t>& select) {
  double sum = 0, sum_d = 0, sum_d2 = 0;
  size_t n = 0;
  for (size_t i = 0; i < a.data.size(); ++i) {
    if (!select[i]) continue;
    const double d = static_cast<double>(a.data[i]) - b.data[i];
    sum += 0.5 * (static_cast<double>(a.data[i]) + b.data[i]);
    sum_d += d;
    sum_d2 += d * d;
    ++n;
  }
  PairStats s;
  s.pixels = n;
  if (n < 2) return s;
  s.mean = sum / n;
  s.variance = 0.5 * (sum_d2 - sum_d * sum_d / n) / (n - 1);
  return s;
}

}  // namespace

void NoiseOptions::Validate() const {
  OptionChecker("NoiseOptions").InRange("exposure_steps", exposure_steps, 3, 16).ThrowIfInvalid();
}

NoiseResult CalibrateNoise(CalibrationRig& rig, const RigCalibration& c, const NoiseOptions& options) {
  options.Validate();
  rig.place_target(Target::kWhite);
  const double metered = MeterWhite(rig, c);
  const CameraInfo info = rig.camera->Info();
  const double shortest = std::max(info.min_exposure_us, metered / 64);
  const size_t pixels = static_cast<size_t>(c.camera_width) * c.camera_height;
  const long total = 2 + 2 * options.exposure_steps + 1;
  long done = 0;

  // Dark pair: the projector black, the shortest exposure.
  ShowPattern(rig, UniformPattern(c, 0));
  const Frame d1 = TakeFrame(rig, shortest), d2 = TakeFrame(rig, shortest);
  Report(rig.progress, {"noise", done += 2, total, "frames"});
  if (d1.data.size() != pixels || d2.data.size() != pixels) {
    throw DeviceError("the camera delivers " + std::to_string(d1.width) + "x" +
                      std::to_string(d1.height) + " frames; the rig file says " +
                      std::to_string(c.camera_width) + "x" + std::to_string(c.camera_height));
  }
  const std::vector<uint8_t> all(pixels, 1);
  const PairStats dark = NoisePair(d1, d2, all);

  // Light pairs under full white.
  ShowPattern(rig, UniformPattern(c, (1 << c.projector_bit_depth) - 1));
  const double max_dn = std::ldexp(1.0, d1.bit_depth) - 1;
  NoiseResult result;
  std::vector<uint8_t> lit(pixels, 0);
  for (size_t i = 0; i < pixels; ++i) lit[i] = c.CameraValid(static_cast<int>(i));
  // The linear range: 70% of the way from black to the nominal saturation (refined below).
  const double linear_limit = 0.7 * (std::min(c.saturation_dn, max_dn) - dark.mean);
  for (int k = 0; k < options.exposure_steps; ++k) {
    const double t = shortest * std::ldexp(1.0, k);
    if (t > info.max_exposure_us) break;
    const Frame a = TakeFrame(rig, t), b = TakeFrame(rig, t);
    Report(rig.progress, {"noise", done += 2, total, "frames"});
    std::vector<uint8_t> select(pixels, 0);
    for (size_t i = 0; i < pixels; ++i) {
      select[i] = lit[i] && 0.5 * (a.data[i] + b.data[i]) - dark.mean < linear_limit;
    }
    const PairStats s = NoisePair(a, b, select);
    if (s.pixels < 100) continue;
    PhotonTransferPoint p;
    p.exposure_us = t;
    p.mean_dn = s.mean - dark.mean;
    p.variance_dn2 = s.variance - dark.variance;
    p.used = p.mean_dn > 5 * std::sqrt(dark.variance);  // well above the read noise floor
    result.points.push_back(p);
  }
  double sxy = 0, sxx = 0;
  for (const PhotonTransferPoint& p : result.points) {
    if (!p.used) continue;
    sxy += p.mean_dn * p.variance_dn2;
    sxx += p.mean_dn * p.mean_dn;
  }
  if (!(sxx > 0 && sxy > 0)) {
    throw DeviceError("noise calibration: no usable photon-transfer points (is the white target "
                      "lit? is the lens cap off?)");
  }
  const double k_dn_per_e = sxy / sxx;  // s2 = K mu
  SensorCalibration& sensor = result.sensor;
  sensor.gain_e_per_dn = 1 / k_dn_per_e;
  sensor.black_dn = dark.mean;
  sensor.read_noise_e = sensor.gain_e_per_dn * std::sqrt(std::max(0.0, dark.variance - 1.0 / 12));

  // Saturation: an overexposed frame; its clipped pixels cluster at the sensor's ceiling.
  const Frame over = TakeFrame(rig, std::min(info.max_exposure_us, metered * 16));
  Report(rig.progress, {"noise", ++done, total, "frames"});
  uint16_t top = 0;
  for (size_t i = 0; i < pixels; ++i) {
    if (lit[i]) top = std::max(top, over.data[i]);
  }
  std::vector<uint16_t> clipped;
  for (size_t i = 0; i < pixels; ++i) {
    if (lit[i] && over.data[i] >= top - 8 * std::sqrt(dark.variance) - 1) clipped.push_back(over.data[i]);
  }
  std::nth_element(clipped.begin(), clipped.begin() + clipped.size() / 2, clipped.end());
  sensor.saturation_dn = clipped[clipped.size() / 2] - 3 * std::sqrt(dark.variance);

  double residual2 = 0;
  int used = 0;
  nlohmann::json points = nlohmann::json::array();
  for (const PhotonTransferPoint& p : result.points) {
    if (p.used) {
      const double r = (p.variance_dn2 - k_dn_per_e * p.mean_dn) / (k_dn_per_e * p.mean_dn);
      residual2 += r * r;
      ++used;
    }
    points.push_back({{"exposure_us", p.exposure_us}, {"mean_dn", p.mean_dn},
                      {"variance_dn2", p.variance_dn2}, {"used", p.used}});
  }
  result.report = {{"gain_e_per_dn", sensor.gain_e_per_dn},
                   {"read_noise_e", sensor.read_noise_e},
                   {"black_dn", sensor.black_dn},
                   {"saturation_dn", sensor.saturation_dn},
                   {"dark_variance_dn2", dark.variance},
                   {"fit_relative_rms", used > 0 ? std::sqrt(residual2 / used) : 0.0},
                   {"points", points},
                   {"nominal", {{"gain_e_per_dn", c.gain_e_per_dn},
                                {"read_noise_e", c.read_noise_e},
                                {"black_dn", c.black_dn},
                                {"saturation_dn", c.saturation_dn}}}};
  return result;
}

void WritePhotonTransferPlot(const std::string& path, const NoiseResult& result) {
  PlotSeries measured{"measured pairs", {}, {}, PlotStyle::kPoints};
  PlotSeries fit{"fit: variance = mean / gain", {}, {}, PlotStyle::kLine};
  double max_mean = 0;
  for (const PhotonTransferPoint& p : result.points) {
    measured.x.push_back(p.mean_dn);
    measured.y.push_back(p.variance_dn2);
    max_mean = std::max(max_mean, p.mean_dn);
  }
  fit.x = {0, max_mean};
  fit.y = {0, max_mean / result.sensor.gain_e_per_dn};
  char title[160];
  std::snprintf(title, sizeof(title), "photon transfer: gain %.3g e-/DN, read noise %.3g e-",
                result.sensor.gain_e_per_dn, result.sensor.read_noise_e);
  WritePlot(path, title, "mean above black (DN)", "temporal variance (DN^2)", {measured, fit});
}

}  // namespace zbrdf
