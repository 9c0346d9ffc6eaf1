// zbrdf process: re-processes a captured session from its frames.
#include <cstdio>
#include <filesystem>
#include <chrono>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "acquisition/capture_job.h"
#include "acquisition/session.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "calibration/calibration_data.h"
#include "rig/direction_maps.h"
#include "tools/cli/command.h"
#include "tools/session_report.h"
#include "tools/terminal_progress.h"
#include "tools/virtual_capture.h"

namespace zbrdf::cli {
namespace {

int RunProcess(const std::vector<std::string>& argv) {
  CommandLine cl(
      "process",
      "Re-processes a session from its frames on disk: checks every journal line against\n"
      "the session's plan and every frame against its journal checksum and its own,\n"
      "merges HDR per pattern, extracts the zonal coefficients and\n"
      "writes zonal.exr and the processing part of report.json. The calibration is the\n"
      "session's own (session.json) unless --calibration names another. Every file is\n"
      "replaced whole (a kill or a full disk leaves the previous zonal.exr); one process\n"
      "writes a session at a time: a second is refused, naming the first's PID.");
  cl.Positional("SESSION", "session folder (from zbrdf capture or zbrdf simulate)")
      .Option("grid", "DTHETA,DPHI", "exitant grid cell size in degrees", "1,2")
      .Option("calibration", "DIR", "calibration folder to apply (default: the session's own, if any)")
      .Flag("no-hdr-images", "do not write the per-pattern HDR images (hdr/)")
      .Flag("json", "print a JSON report instead of the summary");
  if (!cl.Parse(argv)) return 0;
  const std::string dir = cl.Positional(0);
  ProcessingOptions options;
  const std::vector<double> grid = cl.GetDoubles("grid", 2);
  options.theta_step_deg = grid[0];
  options.phi_step_deg = grid[1];
  options.write_hdr_images = !cl.Has("no-hdr-images");
  // The session, its plan, the options and the grid, and that nobody else writes the session:
  // before anything is loaded or written.
  CheckProcessSession(dir, options);
  const Rig rig = SessionRig(dir);
  TerminalProgress progress(cl.Has("json"));
  std::string calibration_folder = cl.Has("calibration") ? cl.Get("calibration") : SessionCalibrationFolder(dir);
  if (!cl.Has("calibration") && !calibration_folder.empty() &&
      !std::filesystem::exists(calibration_folder + "/calibration.json")) {
    std::fprintf(stderr,
                 "zbrdf process: the session's calibration %s is gone; processing with the nominal "
                 "calibration (give --calibration DIR to use another)\n",
                 calibration_folder.c_str());
    calibration_folder.clear();
  }
  const RigCalibration calibration =
      LoadRigCalibration(rig, calibration_folder, DefaultCacheDir(), progress.Callback());
  const auto start = std::chrono::steady_clock::now();
  const ProcessResult r = ProcessSession(dir, calibration, options, "", progress.Callback());
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json report;
  {
    std::ifstream in(SessionPath(dir, kReportFile));
    if (in) report = nlohmann::json::parse(in, nullptr, false);
    if (!report.is_object()) report = nlohmann::json::object();
  }
  report["processing"] = {{"seconds", total},
                          {"read_seconds", r.read_seconds},
                          {"hdr_seconds", r.processing.hdr_seconds},
                          {"hdr_image_seconds", r.processing.image_seconds},
                          {"zonal_seconds", r.processing.zonal_seconds},
                          {"saturated_pixel_lobes", r.processing.saturated_pixels},
                          {"grid_cells_filled", r.processing.filled_cells},
                          {"calibration", calibration.source}};
  if (r.repairs.any()) report["processing"]["repairs"] = r.repairs.Summary();
  try {
    WriteSessionReport(dir, report);  // still under the session's lock (r.lock)
  } catch (const FileWriteError& e) {
    throw e.WithNextStep("run zbrdf process " + dir + " again (zonal.exr is complete)");
  }
  if (cl.Has("json")) {
    std::cout << report["processing"].dump(2) << "\n";
  } else {
    std::printf("processed %s: %zu patterns in %.2f s (reading %.2f s, HDR %.2f s, zonal %.2f s; "
                "HDR images %.2f s beside them) -> %s/zonal.exr\n",
                dir.c_str(), r.plan.lobes.size(), total, r.read_seconds, r.processing.hdr_seconds,
                r.processing.zonal_seconds, r.processing.image_seconds, dir.c_str());
    if (r.repairs.any()) std::printf("  repaired: %s\n", r.repairs.Summary().c_str());
  }
  return 0;
}

const CommandRegistration kProcessCommand({"process",
                                           "re-process a captured session into zonal.exr",
                                           RunProcess});

}  // namespace
}  // namespace zbrdf::cli
