#include "tools/cli/plan_flags.h"

#include <fstream>

#include <nlohmann/json.hpp>

#include "basis/error.h"

namespace zbrdf::cli {

void AddPlanFlags(CommandLine& cl) {
  cl.Option("order", "L", "zonal basis order (0..30): (L+1)^2 functions", "4")
      .Option("zone", "MIN,MAX", "zone in degrees (default: what the rig covers, 1.5 projector pixels inside)")
      .Option("exposures", "N", "exposures per pattern (HDR bracket)", "3")
      .Option("stops", "S", "f-stops between exposures of the bracket", "2")
      .Option("shortest-exposure-us", "T", "shortest exposure (default: metered)")
      .Option("repeats", "N", "captures of each pattern and exposure", "1")
      .Option("grid", "DTHETA,DPHI", "exitant grid cell size in degrees", "1,2")
      .Flag("no-hdr-images", "do not write the per-pattern HDR images (hdr/)")
      .Flag("adaptive", "adaptive capture (docs/adaptive.md): --order is the largest order; bands "
                        "are taken until the last is below the noise floor or --error-target is "
                        "met, and each pattern's second exposure is chosen from its first")
      .Option("error-target", "E", "with --adaptive: stop once the predicted relative coefficient "
                                   "error is below E (e.g. 0.03; default: at the noise floor only)")
      .Option("min-order", "L", "with --adaptive: bands 0..L are always taken (default 1)")
      .Flag("fixed-exposures", "with --adaptive: keep the --exposures/--stops bracket")
      .Flag("all-lobes", "with --adaptive: capture the lobes isotropy makes redundant too")
      .Option("floor", "FILE", "with --adaptive: the rig's systematic floor (floor.json written "
                               "by zbrdf bench; docs/adaptive.md)");
}

void ReadPlanFlags(const CommandLine& cl, CaptureJobOptions* o) {
  o->order = cl.GetInt("order", 0, 30);
  if (cl.Has("zone")) {
    const std::vector<double> zone = cl.GetDoubles("zone", 2);
    o->zone_min_deg = zone[0];
    o->zone_max_deg = zone[1];
    Zone::FromDegrees(zone[0], zone[1]);  // validates
  }
  o->exposures = cl.GetInt("exposures", 1, 10);
  o->stops_apart = cl.GetDouble("stops", 0.1, 8);
  if (cl.Has("shortest-exposure-us")) {
    o->shortest_exposure_us = cl.GetDouble("shortest-exposure-us", 1, 1e8);
  }
  o->repeats = cl.GetInt("repeats", 1, 100);
  const std::vector<double> grid = cl.GetDoubles("grid", 2);
  o->processing.theta_step_deg = grid[0];
  o->processing.phi_step_deg = grid[1];
  o->processing.write_hdr_images = !cl.Has("no-hdr-images");
  o->adaptive.enabled = cl.Has("adaptive");
  if (!o->adaptive.enabled && (cl.Has("error-target") || cl.Has("min-order") ||
                               cl.Has("fixed-exposures") || cl.Has("all-lobes"))) {
    throw InputError("--error-target, --min-order, --fixed-exposures and --all-lobes need --adaptive");
  }
  if (cl.Has("error-target")) o->adaptive.error_target = cl.GetDouble("error-target", 0, 0.99);
  if (cl.Has("min-order")) o->adaptive.min_order = cl.GetInt("min-order", 0, 30);
  o->adaptive.adaptive_exposures = !cl.Has("fixed-exposures");
  o->adaptive.skip_isotropic = !cl.Has("all-lobes");
  if (cl.Has("floor")) {
    if (!o->adaptive.enabled) throw InputError("--floor needs --adaptive");
    std::ifstream in(cl.Get("floor"));
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (!in || j.is_discarded() || !j.contains("floor_profile") || !j["floor_profile"].is_array()) {
      throw InputError("--floor " + cl.Get("floor") + ": not a floor file (JSON with a "
                       "\"floor_profile\" array, as zbrdf bench writes)");
    }
    o->adaptive.floor_profile = j["floor_profile"].get<std::vector<double>>();
  }
}

}  // namespace zbrdf::cli
