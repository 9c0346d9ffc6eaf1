// zbrdf calibrate: measures a rig's geometry, projector, camera noise and gray-card scale into a
// calibration folder, on the virtual rig (optionally with injected faults) or on hardware.
#include <cstdio>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "brdf/material_spec.h"
#include "calibration/calibrate.h"
#include "drivers/hardware_rig.h"
#include "rig/direction_maps.h"
#include "simulate/virtual_rig.h"
#include "tools/cli/command.h"
#include "tools/terminal_progress.h"

namespace zbrdf::cli {
namespace {

// Calibration frames on the virtual rig use noise of their own, so that a calibration and a
// session simulated with the same --seed do not share noise.
constexpr uint64_t kCalibrationSeedOffset = 0x5eed0000;

void PrintSummary(const std::string& step, const nlohmann::json& r) {
  if (step == "geometry") {
    const auto& p = r["parameters"];
    std::printf("geometry: camera offset (%.3f, %.3f, %.3f) mm, tilt (%.3f, %.3f) deg; projector "
                "axial offset %.3f mm, tilt (%.3f, %.3f) deg\n",
                p["camera_offset_x_mm"]["value"].get<double>(), p["camera_offset_y_mm"]["value"].get<double>(),
                p["camera_offset_z_mm"]["value"].get<double>(), p["camera_tilt_x_deg"]["value"].get<double>(),
                p["camera_tilt_y_deg"]["value"].get<double>(), p["projector_offset_z_mm"]["value"].get<double>(),
                p["projector_tilt_x_deg"]["value"].get<double>(), p["projector_tilt_y_deg"]["value"].get<double>());
    std::printf("          residuals: edges %.3f px, mirror edges %.3f px, correspondences %.3f px (%d used); "
                "camera map moved %.3f deg (median) from the design's\n",
                r.value("edge_rms_px", 0.0), r.value("mirror_edge_rms_px", 0.0),
                r.value("correspondence_rms_projector_px", 0.0), r.value("correspondences", 0),
                r["camera_map_change"].value("median_deg", 0.0));
  } else if (step == "noise") {
    std::printf("noise: gain %.4g e-/DN, read noise %.4g e-, black %.2f DN, saturation %.1f DN\n",
                r.value("gain_e_per_dn", 0.0), r.value("read_noise_e", 0.0), r.value("black_dn", 0.0),
                r.value("saturation_dn", 0.0));
  } else if (step == "projector") {
    std::printf("projector: response fitted gamma %.3g, black %.3g%%; flat field p5 %.3f, median %.3f\n",
                r.value("gamma_fit", 0.0), 100 * r.value("black_fraction", 0.0),
                r["projector_flat"].value("p5", 0.0), r["projector_flat"].value("median", 0.0));
  } else if (step == "graycard") {
    const auto s = r["scale_rgb"];
    std::printf("gray card: scale_rgb (%.4g, %.4g, %.4g); after DC matching l1 off by %.2f%%, l2 by %.2f%%\n",
                s[0].get<double>(), s[1].get<double>(), s[2].get<double>(), 100 * r.value("l1_deviation", 0.0),
                100 * r.value("l2_deviation", 0.0));
  }
}

int RunCalibrate(const std::vector<std::string>& argv) {
  CommandLine cl("calibrate",
                 "Calibrates a rig into a calibration folder that captures and `zbrdf process` use:\n"
                 "  geometry   camera and projector misalignment (annulus edges on the white target,\n"
                 "             Gray code through the mirror), direction maps traced anew\n"
                 "  noise      camera gain, read noise, black level, saturation (EMVA 1288 pairs)\n"
                 "  projector  response curve (white target) and flat field (mirror)\n"
                 "  graycard   camera flat field and per-channel scale from an 18% gray card\n"
                 "  all        the four in this order (each uses the ones before it)\n"
                 "On the virtual rig the targets are swapped in by the simulator; with --hardware\n"
                 "you are asked to place each one.");
  cl.Positional("STEP", "geometry, noise, projector, graycard or all")
      .Option("rig", "FILE", "rig description (the design), e.g. rig/rigs/thesis.yaml")
      .Option("out", "DIR", "calibration folder (created, or updated step by step)")
      .Option("preset", "P", "virtual rig: fast or full", "full")
      .Option("faults", "FILE", "virtual rig: YAML of rig fields that differ from the design as built, "
                                "e.g. misalignment or projector gamma (docs/calibration.md)")
      .Option("seed", "N", "virtual rig: seed of the noise", "1")
      .Flag("no-noise", "virtual rig: no sensor noise")
      .Option("hardware", "FILE", "calibrate the hardware of this rig file instead")
      .Flag("json", "print the steps' reports as JSON");
  cl.Epilog(
      "Examples:\n"
      "  zbrdf calibrate all --rig rig/rigs/thesis.yaml --out calib/thesis\n"
      "  zbrdf calibrate geometry --rig rig/rigs/thesis.yaml --preset fast \\\n"
      "      --faults docs/examples/faults.yaml --out /tmp/calib\n"
      "  zbrdf simulate ... --calibration calib/thesis     # capture with it\n"
      "  zbrdf process SESSION --calibration calib/thesis  # or re-process with it\n"
      "Each step writes a figure (geometry.png, noise.png, projector_response.png,\n"
      "projector_flat.png, graycard.png) and its report into calibration.json.");
  if (!cl.Parse(argv)) return 0;
  const std::string step = cl.Positional(0);
  const bool json = cl.Has("json");
  TerminalProgress progress(json);
  CalibrateOptions options;
  options.folder = cl.Get("out");
  options.cache_dir = DefaultCacheDir();
  Rig design = LoadRig(cl.Get("rig"));
  CalibrationRig rig;
  rig.progress = progress.Callback();
  std::unique_ptr<VirtualRig> virtual_rig;
  std::unique_ptr<Camera> camera;
  std::unique_ptr<Projector> projector;
  SteadyClock steady;
  Target placed = Target::kWhite;
  if (cl.Has("hardware")) {
    if (cl.Has("faults")) throw InputError("--faults simulates a rig; it does not apply to --hardware");
    const HardwareRig hardware = LoadHardwareRig(cl.Get("hardware"));
    camera = OpenRigCamera(hardware, &steady);
    projector = OpenRigProjector(hardware);
    rig.camera = camera.get();
    rig.projector = projector.get();
    rig.clock = &steady;
    rig.settle_us = 1e3 * (hardware.sync.mode == SyncMode::kHardware ? hardware.sync.hardware_settle_ms
                                                                     : hardware.sync.software_settle_ms);
    bool first = true;
    rig.place_target = [&, first](Target t) mutable {
      if (!first && t == placed) return;
      first = false;
      placed = t;
      std::fprintf(stderr, "Place the %s on the sample stage, then press Enter (Ctrl-C aborts): ",
                   TargetDescription(t).c_str());
      std::string line;
      if (!std::getline(std::cin, line)) {
        throw InputError("calibration needs the " + TargetDescription(t) +
                         " placed by hand; run zbrdf calibrate from a terminal");
      }
    };
  } else {
    design = ApplyPreset(design, ParsePreset(cl.Get("preset")));
    const Rig as_built = cl.Has("faults") ? ApplyRigOverlay(design, cl.Get("faults")) : design;
    VirtualRig::Options vo;
    vo.seed = static_cast<uint64_t>(cl.GetInt("seed", 0, 1 << 30)) + kCalibrationSeedOffset;
    vo.noise = !cl.Has("no-noise");
    vo.progress = rig.progress;
    virtual_rig = std::make_unique<VirtualRig>(as_built, MakeBrdf(TargetMaterialSpec(placed)), vo);
    rig.camera = &virtual_rig->camera();
    rig.projector = &virtual_rig->projector();
    rig.clock = &virtual_rig->clock();
    rig.settle_us = design.timing.projector_settle_ms * 1e3;
    rig.place_target = [&](Target t) {
      if (t == placed) return;
      placed = t;
      virtual_rig->SetMaterial(MakeBrdf(TargetMaterialSpec(t)));
    };
  }
  const nlohmann::json reports = RunCalibration(step, rig, design, options);
  if (json) {
    std::cout << reports.dump(2) << "\n";
  } else {
    for (auto it = reports.begin(); it != reports.end(); ++it) PrintSummary(it.key(), it.value());
    std::printf("calibration saved in %s (calibration.json and figures)\n", options.folder.c_str());
  }
  return 0;
}

const CommandRegistration kCalibrateCommand(
    {"calibrate", "calibrate a rig: geometry, projector, noise, gray card", RunCalibrate});

}  // namespace
}  // namespace zbrdf::cli
