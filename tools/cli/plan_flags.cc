#include "tools/cli/plan_flags.h"

namespace zbrdf::cli {

void AddPlanFlags(CommandLine& cl) {
  cl.Option("order", "L", "zonal basis order (0..30): (L+1)^2 functions", "4")
      .Option("zone", "MIN,MAX", "zone in degrees (default: what the rig covers, 1.5 projector pixels inside)")
      .Option("exposures", "N", "exposures per pattern (HDR bracket)", "3")
      .Option("stops", "S", "f-stops between exposures of the bracket", "2")
      .Option("shortest-exposure-us", "T", "shortest exposure (default: metered)")
      .Option("repeats", "N", "captures of each pattern and exposure", "1")
      .Option("grid", "DTHETA,DPHI", "exitant grid cell size in degrees", "1,2")
      .Flag("no-hdr-images", "do not write the per-pattern HDR images (hdr/)");
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
}

}  // namespace zbrdf::cli
