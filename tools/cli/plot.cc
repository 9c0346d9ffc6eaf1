// zbrdf plot: polar plots of BRDF slices and, for zonal data, the coefficient energy per band.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "acquisition/session.h"
#include "acquisition/session_brdf.h"
#include "acquisition/zonal.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "brdf/material_spec.h"
#include "brdf/sh_file.h"
#include "pictures/brdf_plots.h"
#include "pictures/image.h"
#include "tools/brdf_input.h"
#include "tools/cli/command.h"

namespace zbrdf::cli {
namespace {

namespace fs = std::filesystem;

std::vector<double> ParseAngles(const std::string& text) {
  std::vector<double> angles;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    const std::string token =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (token.empty() || *end != '\0' || !(v >= 0 && v < 90)) {
      throw InputError(
          "--theta-i must be a comma-separated list of angles in [0, 90) degrees (got '" + text +
          "')");
    }
    angles.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return angles;
}

int RunPlot(const std::vector<std::string>& args) {
  CommandLine cl("plot",
                 "Draws a BRDF for people: polar plots of f_r in the plane of incidence for "
                 "several\nincident elevations (linear and log scale), and, for zonal data (a "
                 "session or a\nzonal.exr), the energy of the coefficients per band l. Writes "
                 "DIR/slices.png,\nDIR/slices-log.png, DIR/band-energy.png and DIR/plot.json "
                 "(the plotted numbers).");
  cl.Positional("INPUT", "session folder, zonal.exr, file or material spec")
      .Option("out", "DIR", "folder for the plots (created if missing)")
      .Option("theta-i", "DEG,...", "incident elevations of the slices", "0,30,60,75")
      .Flag("json", "print plot.json to standard output as well")
      .Epilog("Example:\n  zbrdf plot results/blue-acrylic --out results/blue-acrylic/plots\n\n" +
              BrdfInputHelp());
  if (!cl.Parse(args)) return 0;
  if (!cl.Has("out")) throw InputError("--out is required: the folder for the plots");
  const std::string input_text = cl.Positional(0);
  const std::string dir = cl.Get("out");
  fs::create_directories(dir);
  const std::vector<double> theta_i = ParseAngles(cl.Get("theta-i"));
  nlohmann::json summary = {{"input", input_text}, {"files", nlohmann::json::array()}};

  // Zonal and SH data for the band energy.
  std::string zonal_path, sh_path, truth_spec;
  if (fs::is_directory(input_text)) {
    if (fs::exists(SessionPath(input_text, kZonalFile))) {
      zonal_path = SessionPath(input_text, kZonalFile);
    }
    const std::vector<std::string> sh_files = SessionShFiles(input_text);
    if (!sh_files.empty()) sh_path = sh_files.front();
    if (SessionFolder::Exists(input_text)) {
      try {
        truth_spec = SessionFolder::Open(input_text).material();
      } catch (const InputError&) {
        // A damaged session.json: no true material to plot; the BRDF below says what is wrong.
      }
    }
  } else if (fs::path(input_text).extension() == ".exr" && fs::is_regular_file(input_text)) {
    // A zonal.exr is data to plot, not a BRDF.
    try {
      (void)ResolveBrdfInput(input_text);
    } catch (const InputError&) {
      zonal_path = input_text;
    }
  }

  // Slices: the BRDF INPUT names; for a session without fit, its true material if simulated.
  std::shared_ptr<const Brdf> brdf;
  std::string title;
  if (zonal_path != input_text) {
    try {
      const BrdfInput input = ResolveBrdfInput(input_text);
      brdf = input.brdf;
      title = input.description;
    } catch (const InputError& e) {
      if (!fs::is_directory(input_text)) throw;
      if (!truth_spec.empty()) {
        brdf = MakeBrdf(truth_spec);
        title = "true material of simulated session " + input_text + ": " + truth_spec;
      } else if (zonal_path.empty()) {
        throw;
      } else {
        std::fprintf(stderr, "zbrdf plot: no slices: %s\n", e.what());
      }
    }
  }
  if (brdf) {
    const auto slices = IncidencePlaneSlices(*brdf, theta_i);
    const std::string caption = title.substr(0, 110);
    WritePng(dir + "/slices.png", DrawIncidenceSlices(slices, caption, false));
    WritePng(dir + "/slices-log.png", DrawIncidenceSlices(slices, caption, true));
    summary["brdf"] = brdf->Spec().substr(0, 400);
    summary["slices"] = SlicesJson(slices);
    summary["files"].push_back(dir + "/slices.png");
    summary["files"].push_back(dir + "/slices-log.png");
  }
  std::vector<BandEnergy> energies;
  if (!zonal_path.empty()) energies.push_back(ZonalBandEnergy(ReadZonalExr(zonal_path)));
  if (!sh_path.empty()) energies.push_back(ShBandEnergy(ReadShFile(sh_path)));
  if (!energies.empty()) {
    WritePng(dir + "/band-energy.png",
             DrawBandEnergy(energies, "coefficient energy per band (sum of squares, log scale)"));
    summary["band_energy"] = nlohmann::json::array();
    for (const BandEnergy& e : energies) summary["band_energy"].push_back(BandEnergyJson(e));
    summary["files"].push_back(dir + "/band-energy.png");
  }
  WriteFileAtomically(dir + "/plot.json", summary.dump(1) + "\n");
  if (cl.Has("json")) {
    std::cout << summary.dump(2) << "\n";
  } else {
    std::printf("plotted %s -> %s\n", input_text.c_str(), dir.c_str());
    for (const auto& f : summary["files"]) std::printf("  %s\n", f.get<std::string>().c_str());
  }
  return 0;
}

const CommandRegistration kPlotCommand(
    {"plot", "polar plots of BRDF slices and per-band coefficient energy", RunPlot});

}  // namespace
}  // namespace zbrdf::cli
