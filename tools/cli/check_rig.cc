// zbrdf check-rig: a bounded self-test of the hardware rig a rig file describes (frames arrive,
// patterns display, projector status, dark/white levels, sync latency), pass/fail per item with
// the reason. The checks themselves are drivers/rig_check.h.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "drivers/hardware_rig.h"
#include "drivers/rig_check.h"
#include "tools/cli/command.h"

namespace zbrdf::cli {
namespace {

void Print(const HardwareRig& rig, const RigCheckReport& report, bool json) {
  if (json) {
    nlohmann::json out;
    out["rig"] = rig.source;
    out["sync"] = SyncModeName(rig.sync.mode);
    out["passed"] = report.AllPassed();
    out["seconds"] = report.seconds;
    out["items"] = nlohmann::json::array();
    for (const auto& item : report.items) {
      out["items"].push_back(
          {{"name", item.name}, {"passed", item.passed}, {"detail", item.detail}});
    }
    std::cout << out.dump(2) << "\n";
    return;
  }
  std::cout << "zbrdf check-rig: rig file " << rig.source
            << " (sync: " << SyncModeName(rig.sync.mode) << ")\n";
  int failed = 0;
  for (const auto& item : report.items) {
    failed += item.passed ? 0 : 1;
    std::string name = item.name;
    name.resize(std::max<size_t>(name.size(), 27), ' ');
    std::cout << "  " << (item.passed ? "PASS" : "FAIL") << "  " << name << " " << item.detail
              << "\n";
  }
  char summary[160];
  std::snprintf(summary, sizeof(summary), "%zu checks, %zu passed, %d failed in %.1f s\n",
                report.items.size(), report.items.size() - static_cast<size_t>(failed), failed,
                report.seconds);
  std::cout << summary;
}

// A report for a rig whose devices did not open: the failure, and every other item skipped.
RigCheckReport OpenFailure(const std::string& item, const std::string& reason) {
  RigCheckReport report;
  const char* items[] = {"camera",      "camera.frames", "projector.display",
                         "levels.dark", "levels.white",  "sync.latency"};
  for (const char* name : items) {
    if (item == name) {
      report.items.push_back({name, false, reason});
    } else {
      report.items.push_back({name, false, "skipped: " + item + " did not open"});
    }
  }
  return report;
}

int RunCheckRig(const std::vector<std::string>& args) {
  CommandLine cl("check-rig",
                 "Self-test the hardware rig of a rig file in about 30 seconds: frames arrive, "
                 "patterns display, projector status, dark and white frame levels, and the "
                 "projector-to-camera latency against the settle time. Prints pass/fail per item "
                 "with the reason; exits 1 if any item fails.");
  cl.Option("rig", "FILE", "hardware rig file (see docs/hardware-rig.md)")
      .Option("frames", "N", "frames to grab in the frame test", "10")
      .Option("budget", "SECONDS", "time budget for the whole check", "30")
      .Flag("json", "print one JSON object instead of text")
      .Epilog(
          "Opens the camera by the address in the rig file (no network discovery) and shows\n"
          "black, white and checkerboard patterns full screen on the projector's output.\n"
          "example: zbrdf check-rig --rig docs/examples/lab-rig.yaml");
  if (!cl.Parse(args)) return 0;
  if (!cl.Has("rig")) throw InputError("check-rig needs --rig FILE (see zbrdf check-rig --help)");
  const HardwareRig rig = LoadHardwareRig(cl.Get("rig"));
  RigCheckOptions options;
  options.frames = cl.GetInt("frames", 1, 1000);
  options.budget_s = cl.GetDouble("budget", 1, 3600);
  options.exposure_us = rig.camera.check_exposure_us;
  options.grab_timeout = std::chrono::milliseconds(rig.camera.timeout_ms);
  const bool json = cl.Has("json");

  SteadyClock clock;
  std::unique_ptr<AravisCamera> camera;
  try {
    camera = OpenRigCamera(rig, &clock);
  } catch (const Error& e) {
    Print(rig, OpenFailure("camera", e.what()), json);
    return 1;
  }
  std::unique_ptr<RigProjector> projector;
  try {
    projector = OpenRigProjector(rig);
  } catch (const Error& e) {
    Print(rig, OpenFailure("projector.display", e.what()), json);
    return 1;
  }
  const RigCheckReport report = RunRigCheck(*camera, *projector, &projector->display(),
                                            projector->control(), rig.sync, clock, options);
  Print(rig, report, json);
  return report.AllPassed() ? 0 : 1;
}

const CommandRegistration kCheckRigCommand({"check-rig", "self-test the hardware rig of a rig file",
                                            RunCheckRig});

}  // namespace
}  // namespace zbrdf::cli
