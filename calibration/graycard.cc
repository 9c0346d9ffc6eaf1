#include "calibration/graycard.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>

#include "acquisition/capture_job.h"
#include "acquisition/session.h"
#include "basis/error.h"
#include "basis/quadrature.h"
#include "basis/spherical_harmonics.h"
#include "basis/zonal_basis.h"
#include "brdf/material_spec.h"
#include "calibration/figures.h"
#include "rig/direction_maps.h"

namespace zbrdf {

std::vector<double> LambertianZonalCoefficients(const Zone& zone, int max_l, double rho) {
  // Z_l0 is a polynomial of degree l in cos(theta): Gauss-Legendre in x = cos(theta) with
  // max_l + 2 nodes integrates Z_l0(x) x exactly.
  const ZonalBasis zb(zone, max_l);
  const GaussLegendreRule rule = GaussLegendre(max_l + 2);
  const double a = zone.cos_lower(), b = zone.cos_upper();
  std::vector<double> z(zb.size()), out(max_l + 1, 0.0);
  for (int q = 0; q < static_cast<int>(rule.nodes.size()); ++q) {
    const double x = 0.5 * (a + b) + 0.5 * (b - a) * rule.nodes[q];
    zb.Eval(x, 0.0, z.data());
    for (int l = 0; l <= max_l; ++l) {
      out[l] += rho / M_PI * 2 * M_PI * 0.5 * (b - a) * rule.weights[q] * z[ShIndex(l, 0)] * x;
    }
  }
  return out;
}

GrayCardResult CalibrateGrayCard(CalibrationRig& rig, const Rig& design,
                                 const RigCalibration& calibration,
                                 const PixelField* prior_camera_flat, const std::string& session_dir,
                                 const std::string& pattern_cache_dir) {
  rig.place_target(Target::kGrayCard);
  if (SessionFolder::Exists(session_dir)) {
    std::filesystem::remove_all(session_dir);  // the calibration's own, earlier gray-card session
  }
  RigCalibration base = calibration;
  base.channel_scale = {1, 1, 1};
  CaptureJobOptions job;
  job.out_dir = session_dir;
  job.order = 2;
  job.settle_us = rig.settle_us;
  job.progress = rig.progress;
  job.pattern_cache_dir = pattern_cache_dir;
  job.processing.write_hdr_images = false;
  job.session_extra = {{"kind", "calibration"}, {"target", TargetMaterialSpec(Target::kGrayCard)}};
  const CaptureJobResult capture = RunCaptureJob(design, base, *rig.camera, *rig.projector,
                                                 *rig.clock, job);
  if (!capture.complete) throw InputError("the gray-card capture was interrupted; run the step again");

  // Per-pixel DC response -> the flat-field correction.
  const size_t pixels = base.camera_response.size();
  std::vector<float> dc(pixels, 0.0f);
  std::vector<uint8_t> dc_valid(pixels, 0);
  std::mutex mutex;
  ProcessingOptions processing;
  processing.write_hdr_images = false;
  processing.pixel_values = [&](int k, const std::vector<float>& value, const std::vector<uint8_t>& valid) {
    if (k != 0) return;
    std::lock_guard<std::mutex> lock(mutex);
    dc = value;
    dc_valid = valid;
  };
  ProcessSession(session_dir, base, processing, pattern_cache_dir);
  GrayCardResult result;
  result.camera_flat.width = base.camera_width;
  result.camera_flat.height = base.camera_height;
  result.camera_flat.value.assign(pixels, 0.0f);
  RigCalibration corrected = base;
  for (int ch = -1; ch < 3; ++ch) {
    std::vector<float> values;
    for (int y = 0; y < base.camera_height; ++y) {
      for (int x = 0; x < base.camera_width; ++x) {
        const size_t i = static_cast<size_t>(y) * base.camera_width + x;
        if (dc_valid[i] && dc[i] > 0 && BayerChannel(base.layout, x, y) == ch) values.push_back(dc[i]);
      }
    }
    if (values.empty()) continue;
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    const double median = values[values.size() / 2];
    for (int y = 0; y < base.camera_height; ++y) {
      for (int x = 0; x < base.camera_width; ++x) {
        const size_t i = static_cast<size_t>(y) * base.camera_width + x;
        if (BayerChannel(base.layout, x, y) != ch) continue;
        const float prior = prior_camera_flat ? prior_camera_flat->value[i] : 1.0f;
        // Pixels with no usable DC keep their prior factor.
        const double ratio = dc_valid[i] && dc[i] > 0 ? dc[i] / median : 1.0;
        result.camera_flat.value[i] = static_cast<float>(prior * ratio);
        corrected.camera_response[i] = static_cast<float>(base.camera_response[i] * ratio);
      }
    }
  }

  // Re-processed with the corrected flat field: the card's coefficients.
  ProcessingOptions again;
  again.write_hdr_images = false;
  const ProcessResult processed = ProcessSession(session_dir, corrected, again, pattern_cache_dir);
  const ZonalData& zonal = processed.zonal;
  const std::vector<double> ideal = LambertianZonalCoefficients(zonal.zone(), 2, kGrayCardAlbedo);
  std::array<std::array<double, 3>, 3> raw{};
  double off_axis2 = 0, dc2 = 0;
  for (int ch = 0; ch < 3; ++ch) {
    for (int k = 0; k < ShCount(2); ++k) {
      int l, m;
      ShDegreeOrder(k, &l, &m);
      double sum = 0, weight = 0;
      for (int cell = 0; cell < zonal.grid.cells(); ++cell) {
        const double area = zonal.grid.CellSolidAngle(cell / zonal.grid.n_phi);
        sum += area * zonal.functions[k].value[ch][cell];
        weight += area;
      }
      const double mean = sum / weight;
      if (m == 0) raw[l][ch] = mean;
      else off_axis2 += mean * mean;
      if (k == 0) dc2 += mean * mean;
    }
  }
  for (int ch = 0; ch < 3; ++ch) {
    if (!(raw[0][ch] > 0)) {
      throw DeviceError("gray card: channel " + std::to_string(ch) +
                        " measured no DC response; is the card lit and in place?");
    }
    result.scale_rgb[ch] = ideal[0] / raw[0][ch];
    for (int l = 0; l <= 2; ++l) result.measured[l][ch] = result.scale_rgb[ch] * raw[l][ch];
  }
  nlohmann::json per_channel = nlohmann::json::array();
  for (int ch = 0; ch < 3; ++ch) {
    // l = 1 relative to its own ideal value; l = 2 relative to the DC term, since its ideal
    // value is exactly 0 (see graycard.h).
    const double d1 = std::abs(result.measured[1][ch] - ideal[1]) / std::abs(ideal[1]);
    const double d2 = std::abs(result.measured[2][ch] - ideal[2]) / std::abs(ideal[0]);
    result.l1_deviation = std::max(result.l1_deviation, d1);
    result.l2_deviation = std::max(result.l2_deviation, d2);
    per_channel.push_back({{"l1_deviation", d1}, {"l2_deviation", d2}});
  }
  for (int l = 0; l <= 2; ++l) result.ideal[l] = ideal[l];
  result.report = {{"scale_rgb", result.scale_rgb},
                   {"l1_deviation", result.l1_deviation},
                   {"l2_deviation", result.l2_deviation},
                   {"per_channel", per_channel},
                   {"ideal_z_l0", ideal},
                   {"measured_z_l0_scaled", result.measured},
                   {"off_axis_relative_rms", std::sqrt(off_axis2 / std::max(1e-300, 3 * dc2))},
                   {"zone_deg", {RadToDeg(zonal.theta_min_rad), RadToDeg(zonal.theta_max_rad)}},
                   {"session", session_dir}};
  return result;
}

void WriteGrayCardFigure(const std::string& path, const GrayCardResult& r) {
  std::vector<std::vector<double>> values;
  for (int l = 0; l <= 2; ++l) {
    values.push_back({r.ideal[l], r.measured[l][0], r.measured[l][1], r.measured[l][2]});
  }
  char title[200];
  std::snprintf(title, sizeof(title),
                "gray card, z_l0 scaled to the DC of 18%% Lambertian: l1 off by %.2f%%, l2 by %.2f%% "
                "(of DC)",
                100 * r.l1_deviation, 100 * r.l2_deviation);
  WriteBarChart(path, title, {"l = 0", "l = 1", "l = 2"},
                {"ideal 18% Lambertian", "measured R", "measured G", "measured B"}, values);
}

}  // namespace zbrdf
