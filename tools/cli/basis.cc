// zbrdf basis: the conditioning report for a zone, a zonal order and a conversion target.
#include <cmath>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "basis/conditioning.h"
#include "basis/zone.h"
#include "tools/cli/command.h"

namespace zbrdf::cli {
namespace {

nlohmann::json FiniteOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; }

int RunBasis(const std::vector<std::string>& args) {
  CommandLine cl("basis",
                 "Conditioning report of the zonal basis on a zone and of its conversion to a "
                 "target basis:\nhow exactly the basis is integrated, how ill-conditioned the "
                 "target is on the zone,\nhow much noise the conversion amplifies, and how well "
                 "a random band-limited function\nsurvives the round trip inside and outside the "
                 "zone. Use it to pick --order, --sh-order,\n--target and --tau for a rig.");
  cl.Option("zone", "MIN,MAX", "zone limits theta_min,theta_max in degrees", "9,57")
      .Option("order", "L", "zonal basis order (0..60)", "4")
      .Option("sh-order", "L2", "target basis order (default: the zonal order)")
      .Option("target", "T", "target basis: sh, sh-even, sh-odd or hsh", "sh")
      .Option("tau", "T", "relative singular-value truncation threshold", "1e-13")
      .Option("noise", "R", "relative noise on the moments for the noisy round trip", "1e-3")
      .Option("seed", "N", "seed of the random round-trip function", "1")
      .Flag("json", "print one JSON object instead of the table")
      .Epilog(
          "Examples:\n"
          "  zbrdf basis --zone 9,57 --order 8\n"
          "  zbrdf basis --zone 9,90 --order 10 --target sh-even --json\n\n"
          "Targets (docs/design.md section 3): sh = all real SH; sh-even / sh-odd = SH with l+m "
          "even / odd\n(even or odd about the horizon; for zones reaching 90 deg); hsh = "
          "hemispherical harmonics.");
  if (!cl.Parse(args)) return 0;
  const std::vector<double> zone_deg = cl.GetDoubles("zone", 2);
  ConditioningOptions options;
  const Zone zone = Zone::FromDegrees(zone_deg[0], zone_deg[1]);  // validates
  options.theta_min_rad = zone.theta_min_rad();
  options.theta_max_rad = zone.theta_max_rad();
  options.zb_order = cl.GetInt("order", 0, 60);
  options.target_order = cl.Has("sh-order") ? cl.GetInt("sh-order", 0, 60) : options.zb_order;
  options.target = ParseTargetName(cl.Get("target"));
  options.tau = cl.GetDouble("tau", 0.0, 0.999);
  options.noise_relative = cl.GetDouble("noise", 0.0, 1.0);
  options.seed = static_cast<uint64_t>(cl.GetInt("seed", 0, 1 << 30));
  const ConditioningReport r = AnalyzeConditioning(options);

  if (cl.Has("json")) {
    nlohmann::json j;
    j["zone_deg"] = {zone_deg[0], zone_deg[1]};
    j["order"] = options.zb_order;
    j["sh_order"] = options.target_order;
    j["target"] = TargetName(options.target);
    j["tau"] = options.tau;
    j["zb_functions"] = r.zb_size;
    j["target_functions"] = r.target_size;
    j["zb_orthonormality_max_error"] = r.zb_orthonormality_max_error;
    j["gram_condition_per_m"] = r.gram_condition_per_m;
    j["gram_condition_saturated"] = r.gram_condition_saturated;
    j["shannon_number"] = r.shannon_number;
    j["noise_gain"] = r.noise_gain;
    j["truncated_components"] = r.truncated_components;
    j["underdetermined_components"] = r.underdetermined_components;
    j["largest_singular_value"] = r.largest_singular_value;
    j["smallest_kept_singular_value"] = FiniteOrNull(r.smallest_kept_singular_value);
    j["roundtrip_error_in_zone"] = r.roundtrip_error_in_zone;
    j["roundtrip_error_outside_zone"] =
        r.has_outside ? FiniteOrNull(r.roundtrip_error_outside_zone) : nlohmann::json(nullptr);
    j["noise_relative"] = options.noise_relative;
    j["noisy_roundtrip_error_in_zone"] = r.noisy_roundtrip_error_in_zone;
    j["noisy_roundtrip_error_outside_zone"] =
        r.has_outside ? FiniteOrNull(r.noisy_roundtrip_error_outside_zone) : nlohmann::json(nullptr);
    j["warnings"] = r.warnings;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::printf("zone %s, zonal order %d (%d functions) -> %s order %d (%d functions), tau %.3g\n\n",
              zone.ToString().c_str(), options.zb_order, r.zb_size,
              TargetName(options.target).c_str(), options.target_order, r.target_size,
              options.tau);
  std::printf("  ZB orthonormality, max |G - I|       %.3g   ((L+1) x (2L+1) product rule)\n",
              r.zb_orthonormality_max_error);
  std::printf("  Shannon number (trace of Gram)      %.2f of %d target functions\n",
              r.shannon_number, r.target_size);
  std::printf("  noise gain ||C||_2                  %.3g\n", r.noise_gain);
  std::printf("  singular values kept                %.3g .. %.3g\n",
              r.smallest_kept_singular_value, r.largest_singular_value);
  std::printf("  truncated / underdetermined         %d / %d\n", r.truncated_components,
              r.underdetermined_components);
  std::printf("  round trip, relative L2 in zone     %.3g\n", r.roundtrip_error_in_zone);
  if (r.has_outside) {
    std::printf("  round trip, outside the zone        %.3g   (upper hemisphere)\n",
                r.roundtrip_error_outside_zone);
  }
  std::printf("  with %.2g noise: in zone / outside   %.3g / %.3g\n", options.noise_relative,
              r.noisy_roundtrip_error_in_zone,
              r.has_outside ? r.noisy_roundtrip_error_outside_zone : 0.0);
  std::printf("\n  |m|  cond(Gram of %s on the zone)\n", TargetName(options.target).c_str());
  for (size_t m = 0; m < r.gram_condition_per_m.size(); ++m) {
    if (r.gram_condition_saturated[m]) {
      std::printf("  %3zu  > %.3g (beyond double precision)\n", m, r.gram_condition_per_m[m]);
    } else {
      std::printf("  %3zu  %.3g\n", m, r.gram_condition_per_m[m]);
    }
  }
  for (const std::string& w : r.warnings) std::printf("\nwarning: %s\n", w.c_str());
  return 0;
}

const CommandRegistration kBasisCommand(
    {"basis", "conditioning report of the zonal basis and its SH conversion", RunBasis});

}  // namespace
}  // namespace zbrdf::cli
