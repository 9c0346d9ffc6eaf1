// zbrdf stress: the numerical stability suite (tools/stress.h), as a table or JSON.
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "basis/data_path.h"
#include "basis/error.h"
#include "tools/cli/command.h"
#include "tools/stress.h"
#include "tools/terminal_progress.h"

namespace zbrdf::cli {
namespace {

int RunStress(const std::vector<std::string>& args) {
  CommandLine cl("stress",
                 "Numerical stability suite: extreme orders (up to 30), narrow zones and zones "
                 "touching the\npole or the horizon, extreme materials (chrome, a mirror, black, "
                 "pure diffuse,\nretro-reflective) and damaged frames or files (all black, all "
                 "saturated, NaN / Inf,\nmismatched sizes). Each case must succeed within its "
                 "tolerance or fail with a clear\nerror; it never writes a NaN. Exits 1 if any "
                 "case FAILs. docs/stress.md explains the cases.");
  cl.Option("only", "NAME", "run this case only (names: --list)")
      .Option("group", "G", "run this group only: basis, hdr, zonal or capture")
      .Option("rig", "FILE", "rig file of the capture cases (default: the bundled thesis rig)")
      .Option("work-dir", "DIR",
              "where the cases write their sessions and files (default: a temporary folder, "
              "removed afterwards)")
      .Option("seed", "N", "seed of the simulated captures", "1")
      .Option("samples-per-pixel", "N",
              "incident directions per pixel in the captures (0: the fast preset's)", "64")
      .Flag("list", "list the cases (name, group, what, tolerance) and exit")
      .Flag("json", "print one JSON object instead of the table")
      .Epilog(
          "Examples:\n"
          "  zbrdf stress                          # every case, about 20-40 s on 2 cores\n"
          "  zbrdf stress --list\n"
          "  zbrdf stress --only basis-order30-narrow\n"
          "  zbrdf stress --group capture --work-dir /tmp/stress --json\n\n"
          "JSON keys: cases (each: name, group, what, tolerance, outcome = pass | expected-error |\n"
          "FAIL, error_kind = input | device | numerical | internal | other | null, detail,\n"
          "seconds), passed, expected_errors, failed, seconds.");
  if (!cl.Parse(args)) return 0;
  const bool json = cl.Has("json");

  std::vector<const StressCase*> cases;
  if (cl.Has("only")) {
    cases.push_back(&FindStressCase(cl.Get("only")));
  } else {
    const std::string group = cl.Has("group") ? cl.Get("group") : "";
    if (!group.empty() && group != "basis" && group != "hdr" && group != "zonal" && group != "capture") {
      throw InputError("--group must be basis, hdr, zonal or capture (got " + group + ")");
    }
    for (const StressCase& c : StressCases()) {
      if (group.empty() || c.group == group) cases.push_back(&c);
    }
  }

  if (cl.Has("list")) {
    if (json) {
      nlohmann::json j = nlohmann::json::array();
      for (const StressCase* c : cases) {
        j.push_back({{"name", c->name}, {"group", c->group}, {"what", c->what}, {"tolerance", c->tolerance}});
      }
      std::cout << j.dump(2) << "\n";
      return 0;
    }
    for (const StressCase* c : cases) {
      std::printf("%-30s %-8s %s\n%39s tolerance: %s\n", c->name.c_str(), c->group.c_str(),
                  c->what.c_str(), "", c->tolerance.c_str());
    }
    return 0;
  }

  StressOptions options;
  options.rig_path = cl.Has("rig") ? cl.Get("rig") : DataPath("rig/rigs/thesis.yaml");
  options.seed = static_cast<uint64_t>(cl.GetInt("seed", 0, 1 << 30));
  options.samples_per_pixel = cl.GetInt("samples-per-pixel", 0, 65536);
  const bool temporary = !cl.Has("work-dir");
  options.work_dir = temporary ? (std::filesystem::temp_directory_path() /
                                  ("zbrdf-stress-" + std::to_string(::getpid()))).string()
                               : cl.Get("work-dir");
  std::filesystem::create_directories(options.work_dir);

  std::vector<StressResult> results;
  double total_s = 0;
  {
    TerminalProgress progress(json);
    results = RunStressCases(cases, options, progress.Callback());
  }
  if (temporary) {
    std::error_code ec;
    std::filesystem::remove_all(options.work_dir, ec);
  }
  int passed = 0, expected = 0, failed = 0;
  for (const StressResult& r : results) {
    total_s += r.seconds;
    passed += r.outcome == StressOutcome::kPass;
    expected += r.outcome == StressOutcome::kExpectedError;
    failed += r.outcome == StressOutcome::kFail;
  }

  if (json) {
    nlohmann::json j;
    j["cases"] = nlohmann::json::array();
    for (const StressResult& r : results) j["cases"].push_back(r.ToJson());
    j["passed"] = passed;
    j["expected_errors"] = expected;
    j["failed"] = failed;
    j["seconds"] = total_s;
    std::cout << j.dump(2) << "\n";
  } else {
    std::printf("%-30s %-8s %-15s %7s  detail\n", "case", "group", "outcome", "time");
    for (const StressResult& r : results) {
      std::printf("%-30s %-8s %-15s %6.1fs  %s\n", r.name.c_str(), r.group.c_str(),
                  StressOutcomeName(r.outcome).c_str(), r.seconds, r.detail.c_str());
    }
    std::printf("\n%d passed, %d failed as expected with a clear error, %d FAILED (%.1f s)\n", passed,
                expected, failed, total_s);
  }
  return failed > 0 ? 1 : 0;
}

const CommandRegistration kStressCommand(
    {"stress", "numerical stability suite: extreme orders, zones, materials, frames", RunStress});

}  // namespace
}  // namespace zbrdf::cli
