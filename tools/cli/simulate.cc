// zbrdf simulate: a capture session on the virtual rig, processed end to end, with the error
// against the material's true coefficients.
#include <chrono>
#include <cstdio>
#include <future>
#include <iostream>

#include <nlohmann/json.hpp>

#include "acquisition/capture_job.h"
#include "acquisition/ground_truth.h"
#include "acquisition/processing.h"
#include "acquisition/zonal.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "brdf/material_spec.h"
#include "tools/cli/command.h"
#include "tools/cli/plan_flags.h"
#include "tools/interrupt.h"
#include "tools/session_report.h"
#include "tools/terminal_progress.h"
#include "tools/virtual_capture.h"

namespace zbrdf::cli {
namespace {

using SteadyTime = std::chrono::steady_clock;
double Seconds(SteadyTime::time_point a, SteadyTime::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

int RunSimulate(const std::vector<std::string>& argv) {
  CommandLine cl("simulate",
                 "Simulates a capture session on the virtual rig and processes it end to end:\n"
                 "meters the exposure, plans the patterns, renders every frame through the rig's\n"
                 "optics and sensor, merges HDR, extracts the zonal coefficients (zonal.exr) and\n"
                 "compares them with the material's true coefficients. Every option and the\n"
                 "folder are checked before anything is written; one process writes a session\n"
                 "at a time.");
  cl.Option("rig", "FILE", "rig description, e.g. rig/rigs/thesis.yaml")
      .Option("material", "SPEC", "the sample, e.g. merl:blue-acrylic, lambert:0.18, ggx:alpha=0.2")
      .Option("out", "DIR", "session folder to create: absent or empty (anything else is refused)")
      .Option("preset", "P", "fast (1/4 resolution, for tests) or full (the rig as described)",
              "full")
      .Option("seed", "N", "seed of the simulated noise and integration", "1")
      .Flag("no-noise", "turn the sensor's shot and read noise off")
      .Option("calibration", "DIR",
              "calibration folder (zbrdf calibrate) for patterns and processing")
      .Option("faults", "FILE",
              "YAML of rig fields that differ from the design as built "
              "(misalignment, projector gamma, ...; docs/calibration.md)")
      .Flag("resume",
            "continue an interrupted session in --out (a torn journal line is cut "
            "away, keeping a copy; frames of another plan or session are taken again)")
      .Flag("force-new",
            "--out is not empty: move it aside to DIR.before-<time> (nothing is "
            "deleted) and start a new session there")
      .Option("samples-per-pixel", "N",
              "incident directions the light transport integrates per camera pixel (default: the "
              "rig's simulation.samples_per_pixel, 512 for the thesis rig, twice it at the fast "
              "preset); fewer is faster and noisier (docs/simulator.md)")
      .Option("truth-samples", "N", "samples per exitant point for the true coefficients", "4096")
      .Flag("json", "print a JSON report instead of the summary");
  AddPlanFlags(cl);
  cl.Epilog(
      "Example:\n"
      "  zbrdf simulate --rig rig/rigs/thesis.yaml --material merl:blue-acrylic --order 4 \\\n"
      "      --out results/blue-acrylic --preset fast\n\n"
      "The session folder holds session.json, frames/, journal.jsonl, hdr/, zonal.exr and\n"
      "report.json (docs/session-folder.md). Materials: zbrdf eval --help lists the specs.");
  if (!cl.Parse(argv)) return 0;
  const auto t0 = SteadyTime::now();
  VirtualCaptureArgs args;
  args.preset_name = cl.Get("preset");
  args.rig = ApplyPreset(LoadRig(cl.Get("rig")), ParsePreset(args.preset_name));
  if (cl.Has("samples-per-pixel")) {
    args.rig.simulation.samples_per_pixel = cl.GetInt("samples-per-pixel", 1, 65536);
  }
  args.material_spec = cl.Get("material");
  args.seed = static_cast<uint64_t>(cl.GetInt("seed", 0, 1 << 30));
  args.noise = !cl.Has("no-noise");
  if (cl.Has("calibration")) args.calibration_folder = cl.Get("calibration");
  if (cl.Has("faults")) {
    args.faults_name = cl.Get("faults");
    args.faults_yaml = ReadTextFile(args.faults_name, "faults file");
  }
  CaptureJobOptions& options = args.job;
  options.out_dir = cl.Get("out");
  options.resume = cl.Has("resume");
  options.force_new = cl.Has("force-new");
  ReadPlanFlags(cl, &options);
  const int truth_samples = cl.GetInt("truth-samples", 16, 1 << 20);
  const bool json = cl.Has("json");
  TerminalProgress progress(false);
  options.progress = progress.Callback();
  options.interrupt = InstallInterruptHandler();
  options.on_plan = PrintPlanSummary;
  const std::string out_dir = options.out_dir;
  GroundTruthOptions truth_options;
  truth_options.samples = 1;
  while (truth_options.samples < truth_samples) truth_options.samples *= 2;
  const std::string truth_cache = DefaultCacheDir() + "/truth";
  // Integrated while the frames are captured (EarlyTruth), checked against the capture's layout
  // when it ends.
  EarlyTruth truth_job(truth_options, truth_cache);
  truth_job.StartAtPlan(&args);
  const VirtualCaptureOutcome outcome = RunVirtualCapture(args);
  const CaptureJobResult& result = outcome.result;
  const Brdf& material = *outcome.material;
  const auto t_capture = SteadyTime::now();
  if (!result.complete) {
    std::fprintf(stderr,
                 "zbrdf simulate: interrupted after %d frames; everything captured is journaled in %s.\n"
                 "Continue with the same command plus --resume.\n",
                 result.capture.frames_captured, out_dir.c_str());
    return 130;
  }
  const GroundTruth truth = truth_job.Get(material, result.zonal);
  const double error = CoefficientError(result.zonal, truth);
  const auto t_truth = SteadyTime::now();

  nlohmann::json report = CaptureJobReport(result, outcome.device_time_s);
  report["material"] = material.Spec();
  report["rig"] = args.rig.name;
  report["preset"] = args.preset_name;
  report["samples_per_pixel"] = args.rig.simulation.samples_per_pixel;
  report["seed"] = args.seed;
  report["noise"] = args.noise;
  report["coefficient_error_in_zone"] = error;
  report["truth"] = {{"samples", truth_options.samples}, {"cells", truth.cells.size()}};
  report["transport_entries"] = outcome.transport_entries;
  // Stages overlap: HDR merging runs on its own thread while frames are rendered.
  report["wall_time_s"] = {
      {"simulate", outcome.setup_seconds + result.wall_capture_s - result.processing.hdr_seconds},
      {"patterns", result.pattern_seconds},
      {"hdr", result.processing.hdr_seconds},
      {"zonal", result.processing.zonal_seconds},
      {"hdr_images", result.processing.image_seconds},
      {"truth", Seconds(t_capture, t_truth)},
      {"total", Seconds(t0, t_truth)}};
  try {
    WriteSessionReport(out_dir, report);  // still under the session's lock (result.lock)
  } catch (const FileWriteError& e) {
    throw e.WithNextStep(
        "continue with the same command plus --resume (the frames and zonal.exr "
        "are complete)");
  }
  if (json) {
    std::cout << report.dump(2) << "\n";
  } else {
    std::printf("simulated %s on %s -> %s\n", material.Spec().c_str(), args.rig.name.c_str(),
                out_dir.c_str());
    std::printf("%s", FormatCaptureSummary(report).c_str());
    std::printf("  results: %s/zonal.exr (coefficients), %s/hdr/ (HDR images), %s/report.json\n",
                out_dir.c_str(), out_dir.c_str(), out_dir.c_str());
  }
  return 0;
}

const CommandRegistration kSimulateCommand({"simulate",
                                            "simulate and process a capture session of a material",
                                            RunSimulate});

}  // namespace
}  // namespace zbrdf::cli
