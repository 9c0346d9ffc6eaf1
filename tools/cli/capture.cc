// zbrdf capture: a capture session on a rig: hardware devices (--hardware) or the virtual rig
// (--material), processed into zonal.exr. Interrupted sessions resume from their journal.
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>

#include <nlohmann/json.hpp>

#include "acquisition/capture_job.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "calibration/calibration_data.h"
#include "drivers/hardware_rig.h"
#include "rig/direction_maps.h"
#include "tools/cli/command.h"
#include "tools/cli/plan_flags.h"
#include "tools/interrupt.h"
#include "tools/session_report.h"
#include "tools/terminal_progress.h"
#include "tools/virtual_capture.h"

namespace zbrdf::cli {
namespace {

int RunCaptureCommand(const std::vector<std::string>& argv) {
  CommandLine cl("capture",
                 "Captures a session on a rig and processes it into zonal coefficients:\n"
                 "meters the exposure, shows every basis pattern, takes its exposure bracket,\n"
                 "journals each frame, merges HDR and writes zonal.exr. With --hardware the\n"
                 "camera and projector of a hardware rig file are used; with --material the\n"
                 "virtual rig stands in for them. Ctrl-C stops after the frame in flight;\n"
                 "--resume continues where the journal ends. One process writes a session at a\n"
                 "time: a second capture, resume or process of it is refused, naming the first's\n"
                 "PID. Every option and the folder are checked before anything is written.");
  cl.Option("rig", "FILE", "rig description (optics, sensor, timing), e.g. rig/rigs/thesis.yaml")
      .Option("out", "DIR",
              "session folder: absent or empty (a folder holding anything else is "
              "refused); never overwritten")
      .Option("hardware", "FILE",
              "hardware rig file: camera, projector, sync (docs/hardware-rig.md)")
      .Option("material", "SPEC", "capture this material on the virtual rig instead of hardware")
      .Option("preset", "P", "virtual rig: fast or full", "full")
      .Option("seed", "N", "virtual rig: seed of noise and integration", "1")
      .Option("calibration", "DIR",
              "calibration folder (zbrdf calibrate) for patterns and processing")
      .Option("faults", "FILE",
              "virtual rig: YAML of rig fields that differ from the design as built")
      .Flag("gige-fake",
            "virtual rig: grab its frames through an Aravis GigE Vision fake camera on "
            "127.0.0.1 and the real camera driver (needs port 3956 free)")
      .Option("lost-packets", "R", "with --gige-fake: probability the fake drops each packet", "0")
      .Flag("resume",
            "continue the interrupted session in --out (a torn journal line is cut "
            "away, keeping a copy; frames of another plan or session are taken again)")
      .Flag("force-new",
            "--out is not empty: move it aside to DIR.before-<time> (nothing is "
            "deleted) and start a new session there")
      .Flag("json", "print a JSON report instead of the summary");
  AddPlanFlags(cl);
  cl.Epilog(
      "Examples:\n"
      "  zbrdf capture --rig rig/rigs/thesis.yaml --hardware lab.yaml --out sessions/felt\n"
      "  zbrdf capture --rig rig/rigs/thesis.yaml --material merl:red-fabric --out /tmp/s\n"
      "  zbrdf capture --rig rig/rigs/thesis.yaml --material merl:red-fabric --out /tmp/g \\\n"
      "      --preset fast --gige-fake --lost-packets 0.01\n"
      "  zbrdf capture --rig rig/rigs/thesis.yaml --hardware lab.yaml --out sessions/felt --resume");
  if (!cl.Parse(argv)) return 0;
  if (cl.Has("hardware") == cl.Has("material") && !cl.Has("resume")) {
    throw InputError("give exactly one of --hardware (real devices) and --material (virtual rig)");
  }
  CaptureJobOptions job;
  job.out_dir = cl.Get("out");
  job.resume = cl.Has("resume");
  job.force_new = cl.Has("force-new");
  ReadPlanFlags(cl, &job);
  // Options, the folder and its writer are checked before any device is opened or file written.
  CheckCaptureJob(job);
  TerminalProgress progress(false);
  job.progress = progress.Callback();
  job.interrupt = InstallInterruptHandler();
  job.on_plan = PrintPlanSummary;
  nlohmann::json report;
  CaptureJobResult result;
  if (cl.Has("hardware")) {
    const Rig rig = LoadRig(cl.Get("rig"));
    const HardwareRig hardware = LoadHardwareRig(cl.Get("hardware"));
    SteadyClock clock;
    auto camera = OpenRigCamera(hardware, &clock);
    auto projector = OpenRigProjector(hardware);
    if (cl.Has("faults")) throw InputError("--faults simulates a rig; it does not apply to --hardware");
    if (cl.Has("gige-fake")) {
      throw InputError("--gige-fake serves the virtual rig's frames; with --hardware the camera of "
                       "the hardware rig file is used (for a fake camera there, see "
                       "docs/examples/fake-rig.yaml)");
    }
    const std::string calibration_folder = cl.Has("calibration") ? cl.Get("calibration") : "";
    const RigCalibration calibration =
        LoadRigCalibration(rig, calibration_folder, DefaultCacheDir(), job.progress);
    job.settle_us = 1e3 * (hardware.sync.mode == SyncMode::kHardware ? hardware.sync.hardware_settle_ms
                                                                     : hardware.sync.software_settle_ms);
    // "created" makes the session id (session.json) of two sessions of one rig and plan differ.
    char created[32];
    const std::time_t now = std::time(nullptr);
    std::strftime(created, sizeof(created), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    job.session_extra = {
        {"kind", "hardware"}, {"hardware_rig", cl.Get("hardware")}, {"created", created}};
    if (!calibration_folder.empty()) {
      job.session_extra["calibration_folder"] =
          std::filesystem::absolute(calibration_folder).lexically_normal().string();
    }
    const int64_t start = clock.NowUs();
    result = RunCaptureJob(rig, calibration, *camera, *projector, clock, job);
    report = CaptureJobReport(result, (clock.NowUs() - start) * 1e-6);
  } else {
    VirtualCaptureArgs args;
    args.preset_name = cl.Get("preset");
    args.rig = ApplyPreset(LoadRig(cl.Get("rig")), ParsePreset(args.preset_name));
    if (cl.Has("material")) args.material_spec = cl.Get("material");
    args.seed = static_cast<uint64_t>(cl.GetInt("seed", 0, 1 << 30));
    if (cl.Has("calibration")) args.calibration_folder = cl.Get("calibration");
    if (cl.Has("faults")) {
      args.faults_name = cl.Get("faults");
      args.faults_yaml = ReadTextFile(args.faults_name, "faults file");
    }
    if (cl.Has("gige-fake")) args.camera_link = CameraLink::kGigEFake;
    args.gige.lost_packet_ratio = cl.GetDouble("lost-packets", 0, 0.5);
    if (args.gige.lost_packet_ratio > 0 && !cl.Has("gige-fake")) {
      throw InputError("--lost-packets applies to --gige-fake only");
    }
    args.job = job;
    const VirtualCaptureOutcome outcome = RunVirtualCapture(args);
    result = outcome.result;
    report = CaptureJobReport(result, outcome.device_time_s);
    report["material"] = outcome.material->Spec();
    if (args.camera_link == CameraLink::kGigEFake) {
      report["camera_link"] = "gige-fake";
      report["incomplete_frames_recaptured"] = outcome.incomplete_frames;
    }
  }
  if (!result.complete) {
    std::fprintf(stderr,
                 "zbrdf capture: interrupted after %d frames; everything captured is journaled in %s.\n"
                 "Continue with the same command plus --resume.\n",
                 result.capture.frames_captured, job.out_dir.c_str());
    return 130;
  }
  report["wall_time_s"] = {{"capture", result.wall_capture_s},
                           {"patterns", result.pattern_seconds},
                           {"hdr", result.processing.hdr_seconds},
                           {"zonal", result.processing.zonal_seconds},
                           {"hdr_images", result.processing.image_seconds}};
  try {
    WriteSessionReport(job.out_dir, report);  // still under the session's lock (result.lock)
  } catch (const FileWriteError& e) {
    throw e.WithNextStep(
        "continue with the same command plus --resume (the frames and zonal.exr "
        "are complete)");
  }
  if (cl.Has("json")) {
    std::cout << report.dump(2) << "\n";
  } else {
    std::printf("captured %s\n%s", job.out_dir.c_str(), FormatCaptureSummary(report).c_str());
  }
  return 0;
}

const CommandRegistration kCaptureCommand(
    {"capture", "capture a session on a rig (hardware or virtual) and process it",
     RunCaptureCommand});

}  // namespace
}  // namespace zbrdf::cli
