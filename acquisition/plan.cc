#include "acquisition/plan.h"

#include <cmath>
#include <cstdio>

#include "acquisition/json_integer.h"
#include "basis/error.h"
#include "basis/option_checker.h"

namespace zbrdf {

std::string PlannedLobe::Name() const {
  if (kind == Kind::kDark) return "dark";
  char name[32];
  std::snprintf(name, sizeof(name), "Z%d,%d%c", l, m, kind == Kind::kPositive ? '+' : '-');
  return name;
}

PlannedFrame CapturePlan::Frame(int index) const {
  const int per_lobe = static_cast<int>(exposures_us.size()) * repeats;
  PlannedFrame f;
  f.lobe = index / per_lobe;
  const int within = index % per_lobe;
  f.repeat = within / static_cast<int>(exposures_us.size());
  f.exposure = within % static_cast<int>(exposures_us.size());
  return f;
}

int CapturePlan::FrameIndex(int lobe, int exposure, int repeat) const {
  const int n = static_cast<int>(exposures_us.size());
  return lobe * n * repeats + repeat * n + exposure;
}

nlohmann::json CapturePlan::ToJson() const {
  nlohmann::json j;
  j["zone_deg"] = {RadToDeg(theta_min_rad), RadToDeg(theta_max_rad)};
  j["zone_rad"] = {theta_min_rad, theta_max_rad};
  j["order"] = order;
  j["exposures_us"] = exposures_us;
  j["repeats"] = repeats;
  nlohmann::json lobes_json = nlohmann::json::array();
  for (const PlannedLobe& lobe : lobes) lobes_json.push_back(lobe.Name());
  j["lobes"] = lobes_json;
  j["frames"] = frame_count();
  return j;
}

CapturePlan CapturePlan::FromJson(const nlohmann::json& j) {
  CapturePlan plan;
  try {
    const auto zone = j.at("zone_rad");
    plan.theta_min_rad = zone.at(0).get<double>();
    plan.theta_max_rad = zone.at(1).get<double>();
    Zone(plan.theta_min_rad, plan.theta_max_rad);  // validates
    plan.order = JsonIntegerAt<int>(j, "order", "capture plan");
    plan.exposures_us = j.at("exposures_us").get<std::vector<double>>();
    plan.repeats = JsonIntegerAt<int>(j, "repeats", "capture plan");
    for (const auto& name_json : j.at("lobes")) {
      const std::string name = name_json.get<std::string>();
      PlannedLobe lobe;
      if (name == "dark") {
        lobe.kind = PlannedLobe::Kind::kDark;
      } else {
        int l = 0, m = 0;
        char sign = 0;
        if (std::sscanf(name.c_str(), "Z%d,%d%c", &l, &m, &sign) != 3 || l < 0 || std::abs(m) > l ||
            (sign != '+' && sign != '-')) {
          throw InputError("plan lobe '" + name + "' is not 'dark' or 'Zl,m+' / 'Zl,m-'");
        }
        lobe.kind = sign == '+' ? PlannedLobe::Kind::kPositive : PlannedLobe::Kind::kNegative;
        lobe.l = l;
        lobe.m = m;
      }
      plan.lobes.push_back(lobe);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("capture plan: missing or malformed field (") + e.what() + ")");
  }
  if (plan.order < 0 || plan.order > 30 || plan.repeats < 1 || plan.exposures_us.empty() ||
      plan.lobes.empty()) {
    throw InputError("capture plan: order, repeats, exposures or lobes out of range");
  }
  for (double t : plan.exposures_us) {
    if (!(t > 0 && std::isfinite(t))) throw InputError("capture plan: exposures must be > 0");
  }
  return plan;
}

void PlanOptions::Validate() const {
  OptionChecker check("PlanOptions");
  check.ValidZone("theta_min_rad, theta_max_rad", theta_min_rad, theta_max_rad)
      .InRange("order", order, 0, 30)
      .InRange("exposures", exposures, 1, 10)
      .InRangeAbove("stops_apart", stops_apart, 0, 8)
      .Positive("shortest_exposure_us", shortest_exposure_us)
      .InRange("repeats", repeats, 1, 100)
      .ThrowIfInvalid();
}

CapturePlan MakePlan(const PlanOptions& o) {
  o.Validate();
  CapturePlan plan;
  const Zone zone(o.theta_min_rad, o.theta_max_rad);  // validates
  plan.theta_min_rad = zone.theta_min_rad();
  plan.theta_max_rad = zone.theta_max_rad();
  plan.order = o.order;
  plan.repeats = o.repeats;
  for (int e = 0; e < o.exposures; ++e) {
    plan.exposures_us.push_back(o.shortest_exposure_us * std::pow(2.0, o.stops_apart * e));
  }
  plan.lobes.push_back({PlannedLobe::Kind::kDark, 0, 0});
  for (int l = 0; l <= o.order; ++l) {
    for (int m = -l; m <= l; ++m) {
      plan.lobes.push_back({PlannedLobe::Kind::kPositive, l, m});
      // Z_00 is a positive constant: its negative part is empty. Every other Z_lm changes sign
      // over the zone (orthogonality to Z_00 forces a zero mean).
      if (l > 0) plan.lobes.push_back({PlannedLobe::Kind::kNegative, l, m});
    }
  }
  return plan;
}

double PredictCaptureTimeS(const CapturePlan& plan, const TimingParams& timing) {
  const double period_s = 1.0 / timing.frame_rate_hz;
  double total = 0;
  for (size_t lobe = 0; lobe < plan.lobes.size(); ++lobe) {
    total += timing.projector_settle_ms * 1e-3;
    for (int r = 0; r < plan.repeats; ++r) {
      for (double t : plan.exposures_us) total += std::max(period_s, t * 1e-6 + timing.readout_ms * 1e-3);
    }
  }
  return total;
}

void DefaultZone(double covered_min_rad, double covered_max_rad, double margin_deg,
                 double* theta_min_rad, double* theta_max_rad) {
  const double lo = std::ceil((RadToDeg(covered_min_rad) + margin_deg) * 10 - 1e-9) / 10;
  const double hi = std::floor((RadToDeg(covered_max_rad) - margin_deg) * 10 + 1e-9) / 10;
  if (!(hi > lo)) {
    throw InputError("the rig covers too narrow a zone (" + std::to_string(RadToDeg(covered_min_rad)) +
                     " to " + std::to_string(RadToDeg(covered_max_rad)) + " deg) to measure");
  }
  *theta_min_rad = DegToRad(lo);
  *theta_max_rad = DegToRad(hi);
}

}  // namespace zbrdf
