// zbrdf design-dome: the dome profile of a rig by Euler integration, a drawing and the report.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "basis/zone.h"
#include "rig/optics.h"
#include "tools/cli/command.h"
#include "pictures/dome_drawing.h"

namespace zbrdf::cli {
namespace {

int RunDesignDome(const std::vector<std::string>& args) {
  CommandLine cl("design-dome",
                 "Designs the rig's freeform dome by Euler integration of the reflector ODE "
                 "(docs/design.md section 1):\nfrom the parabola's rim ray inward, each dome "
                 "point's normal bisects the incoming camera ray\nand the direction to the sample "
                 "center. Writes the profile (CSV) and a cross-section drawing\n(PNG) with "
                 "chief-ray paths, and reports the measured zone, its share of the hemisphere\n"
                 "and the camera pixels per degree of theta.");
  cl.Option("rig", "FILE", "rig description (YAML), e.g. rig/rigs/thesis.yaml")
      .Option("out", "DIR", "folder for dome-profile.csv and dome-cross-section.png")
      .Flag("json", "print the report as JSON");
  if (!cl.Parse(args)) return 0;
  const Rig rig = LoadRig(cl.Get("rig"));
  const std::string out = cl.Get("out");
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) throw InputError("cannot create output folder " + out + ": " + ec.message());
  const OpticalSystem optics(rig);
  const DomeDesign& d = optics.design();
  const std::string csv = out + "/dome-profile.csv", png = out + "/dome-cross-section.png";
  WriteDomeProfileCsv(d, csv);
  DrawDomeCrossSection(optics, png);
  double r_max = 0, z_max = 0;
  for (const auto& p : d.profile) {
    r_max = std::max(r_max, p.r_mm);
    z_max = std::max(z_max, p.z_mm);
  }
  if (cl.Has("json")) {
    nlohmann::json j;
    j["rig"] = rig.name;
    j["zone_deg"] = {RadToDeg(d.zone_min_rad), RadToDeg(d.zone_max_rad)};
    j["coverage_fraction"] = d.coverage_fraction;
    j["pixels_per_degree_min"] = d.pixels_per_degree_min;
    j["pixels_per_degree_mean"] = d.pixels_per_degree_mean;
    j["parabola_shadow_deg"] = RadToDeg(d.parabola_shadow_rad);
    j["top_hole_radius_mm"] = d.top_hole_radius_mm;
    j["dome_diameter_mm"] = 2 * r_max;
    j["dome_height_mm"] = z_max;
    j["profile_points"] = d.profile.size();
    j["profile_csv"] = csv;
    j["cross_section_png"] = png;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::printf("rig %s: dome designed with %zu profile points\n", rig.name.c_str(), d.profile.size());
  std::printf("  measured zone            %.2f .. %.2f deg (parabola shadow %.2f deg)\n",
              RadToDeg(d.zone_min_rad), RadToDeg(d.zone_max_rad), RadToDeg(d.parabola_shadow_rad));
  std::printf("  coverage                 %.1f%% of the hemisphere's solid angle\n",
              100 * d.coverage_fraction);
  std::printf("  camera pixels / degree   min %.2f, mean %.2f\n", d.pixels_per_degree_min,
              d.pixels_per_degree_mean);
  std::printf("  dome                     %.0f mm across, %.0f mm high, top hole %.1f mm radius\n",
              2 * r_max, z_max, d.top_hole_radius_mm);
  std::printf("wrote %s and %s\n", csv.c_str(), png.c_str());
  return 0;
}

const CommandRegistration kDesignDomeCommand(
    {"design-dome", "design the dome profile of a rig; drawing and zone report", RunDesignDome});

}  // namespace
}  // namespace zbrdf::cli
