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

CapturePlan CapturePlan::FromJson(const nlohmann::json& j, const std::string& where) {
  CapturePlan plan;
  const std::string what = where + " field";
  if (!j.is_object()) throw InputError(where + " is not a JSON object");
  // Each field is checked for presence and type before it is read, so that a message names it.
  const auto field = [&](const char* key) -> const nlohmann::json& {
    if (!j.contains(key)) throw InputError(what + " '" + key + "' is missing");
    return j.at(key);
  };
  const auto number = [&](const nlohmann::json& v, const std::string& name) {
    if (!v.is_number()) {
      throw InputError(what + " '" + name + "' must be a number (got " + v.dump() + ")");
    }
    return v.get<double>();
  };
  const nlohmann::json& zone = field("zone_rad");
  if (!zone.is_array() || zone.size() != 2) {
    throw InputError(what + " 'zone_rad' must be [theta_min, theta_max] in radians (got " +
                     zone.dump() + ")");
  }
  plan.theta_min_rad = number(zone[0], "zone_rad[0]");
  plan.theta_max_rad = number(zone[1], "zone_rad[1]");
  try {
    Zone(plan.theta_min_rad, plan.theta_max_rad);  // validates
  } catch (const InputError& e) {
    throw InputError(what + " 'zone_rad': " + e.what());
  }
  plan.order = JsonIntegerAt<int>(j, "order", where);
  const nlohmann::json& exposures = field("exposures_us");
  if (!exposures.is_array()) {
    throw InputError(what + " 'exposures_us' must be an array of exposures in us");
  }
  for (size_t k = 0; k < exposures.size(); ++k) {
    plan.exposures_us.push_back(number(exposures[k], "exposures_us[" + std::to_string(k) + "]"));
  }
  plan.repeats = JsonIntegerAt<int>(j, "repeats", where);
  const nlohmann::json& lobes = field("lobes");
  if (!lobes.is_array()) throw InputError(what + " 'lobes' must be an array of lobe names");
  for (const auto& name_json : lobes) {
    if (!name_json.is_string()) {
      throw InputError(what + " 'lobes' holds " + name_json.dump() + ", not a lobe name");
    }
    const std::string name = name_json.get<std::string>();
    PlannedLobe lobe;
    if (name == "dark") {
      lobe.kind = PlannedLobe::Kind::kDark;
    } else {
      int l = 0, m = 0;
      char sign = 0;
      if (std::sscanf(name.c_str(), "Z%d,%d%c", &l, &m, &sign) != 3 || l < 0 || std::abs(m) > l ||
          (sign != '+' && sign != '-')) {
        throw InputError(what + " 'lobes': '" + name + "' is not 'dark' or 'Zl,m+' / 'Zl,m-'");
      }
      lobe.kind = sign == '+' ? PlannedLobe::Kind::kPositive : PlannedLobe::Kind::kNegative;
      lobe.l = l;
      lobe.m = m;
    }
    plan.lobes.push_back(lobe);
  }
  if (plan.order < 0 || plan.order > 30 || plan.repeats < 1 || plan.exposures_us.empty() ||
      plan.lobes.empty()) {
    throw InputError(where +
                     ": order (0..30), repeats (>= 1), exposures_us or lobes (not empty) "
                     "out of range");
  }
  for (double t : plan.exposures_us) {
    if (!(t > 0 && std::isfinite(t))) throw InputError(what + " 'exposures_us' must all be > 0");
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
