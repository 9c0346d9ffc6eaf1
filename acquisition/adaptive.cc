#include "acquisition/adaptive.h"

#include <algorithm>
#include <cmath>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/spherical_harmonics.h"

namespace zbrdf {

void AdaptiveOptions::Validate() const {
  OptionChecker check("AdaptiveOptions");
  check.InRange("min_order", min_order, 0, 30)
      .InRangeBelow("error_target", error_target, 0, 1)  // a relative error; 0: none
      .InRangeBelow("isotropy_threshold", isotropy_threshold, 0, 1);  // 0: never isotropic
  for (size_t i = 0; i < floor_profile.size(); ++i) {
    check.Require(floor_profile[i] >= 0 && std::isfinite(floor_profile[i]),
                  "floor_profile[" + std::to_string(i) + "]",
                  "must be >= 0 and finite (got " + FormatOptionValue(floor_profile[i]) + ")");
  }
  check.InRangeAbove("noise_ratio", noise_ratio, 0, 100)
      // The plan brackets t0 and max_ratio t0, at most 8 f-stops apart (MakePlan).
      .InRange("max_ratio", max_ratio, 1, 256)
      .InRangeAbove("clip_quantile", clip_quantile, 0.5, 1)
      // The HDR merge drops samples above 0.95 of the range.
      .Require(target_level > 0 && target_level < 0.95, "target_level",
               "must be in (0, 0.95) of the range: the HDR merge drops samples above 0.95 (got " +
                   FormatOptionValue(target_level) + ")")
      .ThrowIfInvalid();
}

nlohmann::json AdaptiveOptions::ToJson() const {
  return {{"enabled", enabled},
          {"isotropy_threshold", isotropy_threshold},
          {"floor_profile", floor_profile},
          {"min_order", min_order},
          {"error_target", error_target},
          {"noise_ratio", noise_ratio},
          {"adaptive_exposures", adaptive_exposures},
          {"skip_isotropic", skip_isotropic},
          {"max_ratio", max_ratio},
          {"clip_quantile", clip_quantile},
          {"target_level", target_level}};
}

AdaptiveOptions AdaptiveOptions::FromJson(const nlohmann::json& j) {
  AdaptiveOptions o;
  if (!j.is_object()) throw InputError("adaptive options: not a JSON object");
  o.enabled = j.value("enabled", o.enabled);
  o.isotropy_threshold = j.value("isotropy_threshold", o.isotropy_threshold);
  if (j.contains("floor_profile")) o.floor_profile = j["floor_profile"].get<std::vector<double>>();
  o.min_order = j.value("min_order", o.min_order);
  o.error_target = j.value("error_target", o.error_target);
  o.noise_ratio = j.value("noise_ratio", o.noise_ratio);
  o.adaptive_exposures = j.value("adaptive_exposures", o.adaptive_exposures);
  o.skip_isotropic = j.value("skip_isotropic", o.skip_isotropic);
  o.max_ratio = j.value("max_ratio", o.max_ratio);
  o.clip_quantile = j.value("clip_quantile", o.clip_quantile);
  o.target_level = j.value("target_level", o.target_level);
  o.Validate();
  return o;
}

AdaptiveBand MeasureBandEnergy(int l, const std::vector<const GridImage*>& functions,
                               const ExitantGrid& grid) {
  AdaptiveBand band;
  band.l = l;
  // The harmonic each z_lm(w_r) has for an isotropic material, sampled at the cell centres.
  std::vector<std::vector<double>> harmonic(functions.size(), std::vector<double>(grid.n_phi));
  for (size_t f = 0; f < functions.size(); ++f) {
    const int m = static_cast<int>(f) - l;
    for (int j = 0; j < grid.n_phi; ++j) {
      const double phi = (j + 0.5) * grid.phi_step_rad;
      harmonic[f][j] = m > 0 ? std::cos(m * phi) : m < 0 ? std::sin(-m * phi) : 1.0;
    }
  }
  for (size_t f = 0; f < functions.size(); ++f) {
    if (!functions[f]) continue;
    const std::vector<double>& h = harmonic[f];
    double h_norm = 0;
    for (double v : h) h_norm += v * v;
    for (int ch = 0; ch < 3; ++ch) {
      const std::vector<float>& value = functions[f]->value[ch];
      const std::vector<float>& variance = functions[f]->variance[ch];
      if (value.size() != static_cast<size_t>(grid.cells())) continue;  // not processed
      for (int i = 0; i < grid.n_theta; ++i) {
        const double omega = grid.CellSolidAngle(i);
        double row = 0, dot = 0;
        for (int j = 0; j < grid.n_phi; ++j) {
          const size_t c = static_cast<size_t>(i) * grid.n_phi + j;
          row += double(value[c]) * value[c];
          dot += value[c] * h[j];
          if (c < variance.size()) band.noise += omega * double(variance[c]);
        }
        band.energy += omega * row;
        // Least-squares fit of the row by its harmonic; what is left over.
        band.off_harmonic += omega * std::max(0.0, row - dot * dot / h_norm);
      }
    }
  }
  band.floor = band.noise;
  return band;
}

std::vector<double> FloorProfile(const std::vector<AdaptiveBand>& bands) {
  std::vector<double> profile;
  double below = 0;
  for (const AdaptiveBand& b : bands) {
    profile.push_back(below > 0 ? b.energy / below : 0.0);
    below += b.energy;
  }
  // Bands 0 and 1 of a Lambertian target are its signal, not a floor.
  for (size_t l = 0; l < profile.size() && l < 2; ++l) profile[l] = 0;
  return profile;
}

AdaptiveDecision DecideAfterBand(const std::vector<AdaptiveBand>& bands,
                                 const AdaptiveOptions& options) {
  AdaptiveDecision d;
  if (bands.empty()) return d;
  const int l = bands.back().l;
  d.order = l;
  double signal = 0, noise = 0;
  for (const AdaptiveBand& b : bands) {
    signal += std::max(0.0, b.signal());
    noise += b.floor;
  }
  // Geometric tail from the last two bands, ratio capped at 0.9 (a tail of at most 9 bands'
  // worth): bands of smooth BRDFs decay roughly geometrically in l.
  double tail = 0;
  if (bands.size() >= 2) {
    const double last = std::max(0.0, bands.back().signal());
    const double before = std::max(0.0, bands[bands.size() - 2].signal());
    const double q = before > 0 ? std::min(0.9, last / before) : 0.9;
    tail = last * q / (1 - q);
  }
  d.predicted_error = signal > 0 ? std::sqrt((noise + tail) / signal) : 1.0;
  if (l <= options.min_order) return d;
  const AdaptiveBand& last = bands.back();
  if (last.signal() < options.noise_ratio * last.floor) {
    // Keeping the band would add more noise than signal: drop it and stop.
    d.stop = true;
    d.order = l - 1;
    d.reason = "noise floor";
    double s = 0, n = 0;
    for (size_t i = 0; i + 1 < bands.size(); ++i) {
      s += std::max(0.0, bands[i].signal());
      n += bands[i].floor;
    }
    d.predicted_error = s > 0 ? std::sqrt((n + std::max(0.0, last.signal())) / s) : 1.0;
    return d;
  }
  if (options.error_target > 0 && d.predicted_error <= options.error_target) {
    d.stop = true;
    d.reason = "error target";
  }
  return d;
}

double AdaptiveExposureUs(const Frame& first, const RigCalibration& c,
                          const AdaptiveOptions& options) {
  const double range = c.saturation_dn - c.black_dn;
  std::vector<float> signal;
  signal.reserve(first.data.size());
  for (size_t i = 0; i < first.data.size(); ++i) {
    if (c.CameraValid(static_cast<int>(i))) {
      signal.push_back(std::max(0.0f, static_cast<float>(first.data[i] - c.black_dn)));
    }
  }
  if (signal.empty()) return first.exposure_us * options.max_ratio;
  const size_t q =
      std::min(signal.size() - 1,
               static_cast<size_t>(std::floor(options.clip_quantile * (signal.size() - 1))));
  std::nth_element(signal.begin(), signal.begin() + q, signal.end());
  const double level = signal[q];
  // A quantile at or below one DN says only that the pattern is dark: take the longest.
  const double ratio = level > 1 ? options.target_level * range / level : options.max_ratio;
  return first.exposure_us * std::clamp(ratio, 1.0, options.max_ratio);
}

CapturePlan TruncatePlan(const CapturePlan& plan, int order) {
  if (order < 0 || order > plan.order) {
    throw InputError("cannot truncate an order-" + std::to_string(plan.order) + " plan to order " +
                     std::to_string(order));
  }
  CapturePlan out = plan;
  out.order = order;
  out.lobes.clear();
  for (const PlannedLobe& lobe : plan.lobes) {
    if (lobe.kind == PlannedLobe::Kind::kDark || lobe.l <= order) out.lobes.push_back(lobe);
  }
  // Frame indices are positional: what is kept must be a prefix of the plan.
  for (size_t i = 0; i < out.lobes.size(); ++i) {
    if (out.lobes[i].Name() != plan.lobes[i].Name()) {
      throw InputError("the plan's lobes do not come band by band; it cannot be truncated");
    }
  }
  return out;
}

AdaptiveController::AdaptiveController(const CapturePlan& plan, const RigCalibration& calibration,
                                       const AdaptiveOptions& options, ZonalProcessor* processor)
    : plan_(plan),
      calibration_(calibration),
      options_(options),
      processor_(processor),
      order_(plan.order) {
  options_.Validate();
  band_end_.assign(plan.order + 1, -1);
  for (size_t i = 0; i < plan.lobes.size(); ++i) {
    const PlannedLobe& lobe = plan.lobes[i];
    if (lobe.kind == PlannedLobe::Kind::kDark) continue;
    if (i > 0 && plan.lobes[i - 1].kind != PlannedLobe::Kind::kDark &&
        plan.lobes[i - 1].l > lobe.l) {
      throw InputError("adaptive capture needs a plan whose lobes come band by band");
    }
    band_end_[lobe.l] = static_cast<int>(i);
  }
}

double AdaptiveController::ExposureUs(int lobe, int exposure,
                                      const std::vector<const Frame*>& shorter) const {
  if (!options_.adaptive_exposures || shorter.empty()) return plan_.exposures_us.at(exposure);
  (void)lobe;
  return AdaptiveExposureUs(*shorter.front(), calibration_, options_);
}

bool AdaptiveController::WouldSkipLobe(int lobe) const {
  const PlannedLobe& p = plan_.lobes.at(lobe);
  if (!options_.skip_isotropic || !isotropic_ || p.kind == PlannedLobe::Kind::kDark ||
      p.l <= std::max(1, options_.min_order)) {
    return false;
  }
  return p.m < 0 || (p.m > 0 && p.kind == PlannedLobe::Kind::kNegative);
}

bool AdaptiveController::SkipLobe(int lobe) {
  const bool skip = WouldSkipLobe(lobe);
  if (skip) skipped_.push_back(plan_.lobes.at(lobe).Name());
  return skip;
}

bool AdaptiveController::StopAfterLobe(int lobe) {
  int l = -1;
  for (int b = 0; b <= plan_.order; ++b) {
    if (band_end_[b] == lobe) l = b;
  }
  if (l < 0 || !processor_) return false;
  processor_->Wait();
  processor_->SynthesizeIsotropic(l);
  std::vector<const GridImage*> functions;
  for (int m = -l; m <= l; ++m) functions.push_back(&processor_->Function(ShIndex(l, m)));
  bands_.push_back(MeasureBandEnergy(l, functions, processor_->grid()));
  if (isotropic_ && options_.skip_isotropic && l > std::max(1, options_.min_order)) {
    // Synthesized functions are single harmonics by construction: the isotropy residual of the
    // band is estimated from its measured z_l0, per function.
    std::vector<const GridImage*> zonal(2 * l + 1, nullptr);
    zonal[l] = functions[l];
    bands_.back().off_harmonic =
        (2 * l + 1) * MeasureBandEnergy(l, zonal, processor_->grid()).off_harmonic;
  }
  if (l <= std::max(1, options_.min_order)) {
    double off = 0, energy = 0;
    for (const AdaptiveBand& b : bands_) {
      off += b.off_harmonic;
      energy += b.energy;
    }
    isotropic_ = energy > 0 && off < options_.isotropy_threshold * energy;
  }
  AdaptiveBand& band = bands_.back();
  if (isotropic_) band.floor = std::max(band.noise, band.off_harmonic);
  if (static_cast<size_t>(l) < options_.floor_profile.size()) {
    double below = 0;
    for (size_t i = 0; i + 1 < bands_.size(); ++i) below += bands_[i].energy;
    band.floor = std::max(band.floor, options_.floor_profile[l] * below);
  }
  decision_ = DecideAfterBand(bands_, options_);
  if (decision_.stop) {
    order_ = decision_.order;
    return true;
  }
  order_ = l == plan_.order ? plan_.order : order_;
  return false;
}

nlohmann::json AdaptiveController::Report() const {
  nlohmann::json bands = nlohmann::json::array();
  for (const AdaptiveBand& b : bands_) {
    bands.push_back({{"l", b.l},
                     {"energy", b.energy},
                     {"noise", b.noise},
                     {"off_harmonic", b.off_harmonic},
                     {"floor", b.floor}});
  }
  return {{"options", options_.ToJson()},
          {"max_order", plan_.order},
          {"order", order_},
          {"reason", decision_.stop ? decision_.reason : std::string("max order")},
          {"predicted_error", decision_.predicted_error},
          {"isotropic", isotropic_},
          {"skipped_lobes", skipped_},
          {"bands", bands}};
}

}  // namespace zbrdf
