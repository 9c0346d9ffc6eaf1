// zbrdf preview-bench: MIS, SIR and SMC on a turntable, error against time.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "tools/cli/command.h"
#include "tools/relight_bench.h"
#include "tools/terminal_progress.h"

namespace zbrdf::cli {
namespace {

int RunPreviewBench(const std::vector<std::string>& args) {
  CommandLine cl("preview-bench",
                 "Renders a turntable (the environment turned about the vertical axis) of each\n"
                 "material with each relighting sampler (mis, sir, smc, smc-bridges; zbrdf\n"
                 "preview --sampler) at each budget, and compares every frame with a converged\n"
                 "reference: relative RMSE against seconds per frame, and each sampler's error at\n"
                 "SIR's frame time (equal time). Writes DIR/relight-bench.json, .csv,\n"
                 "rmse-vs-time.png and frames-<material>.png. docs/preview.md has the measured\n"
                 "table.");
  cl.Option("out", "DIR", "folder for the results")
      .Option("materials", "LIST",
              "material inputs (see zbrdf preview --help); built in: glossy-dbrdf, diffuse",
              "glossy-dbrdf,diffuse")
      .Option("environment", "E", "studio, sky or an .exr / .hdr lat-long map", "studio")
      .Option("size", "N", "image width and height in pixels", "64")
      .Option("frames", "N", "turntable frames (one turn unless --degrees-per-frame)", "30")
      .Option("degrees-per-frame", "D", "the environment's turn between frames; 0: 360 / frames",
              "0")
      .Option("budgets", "LIST", "samples (MIS) or particles (the others) per pixel", "2,4,8,16")
      .Option("reference-spp", "N", "MIS samples per pixel of the reference", "2048")
      .Option("history-weight", "H", "SMC: the carried particles' weight (zbrdf preview)", "1")
      .Option("bridges", "K", "SMC bridges: intermediate distributions per frame", "2")
      .Option("ess-threshold", "F", "SMC bridges: resample when ESS < F x particles", "0.5")
      .Option("seed", "N", "seed", "1")
      .Flag("json", "print the summary and the equal-time table as JSON");
  cl.Epilog(
      "Examples:\n  zbrdf preview-bench --out results/relight --frames 30\n"
      "  zbrdf preview-bench --out results/relight-slow --frames 30 --degrees-per-frame 1\n");
  if (!cl.Parse(args)) return 0;
  if (!cl.Has("out")) throw InputError("--out is required: the folder for the results");
  RelightBenchOptions options;
  options.out_dir = cl.Get("out");
  options.materials = cl.GetList("materials");
  options.environment = cl.Get("environment");
  options.size = cl.GetInt("size", 8, 1024);
  options.frames = cl.GetInt("frames", 1, 10000);
  options.degrees_per_frame = cl.GetDouble("degrees-per-frame", 0.0, 360.0);
  options.budgets.clear();
  for (const std::string& b : cl.GetList("budgets")) {
    char* end = nullptr;
    const long v = std::strtol(b.c_str(), &end, 10);
    if (end == b.c_str() || *end != '\0' || v < 1 || v > 1 << 16) {
      throw InputError("--budgets: '" + b + "' is not a whole number from 1 to 65536");
    }
    options.budgets.push_back(static_cast<int>(v));
  }
  options.reference_spp = cl.GetInt("reference-spp", 1, 1 << 20);
  options.history_weight = cl.GetDouble("history-weight", 1e-3, 1e3);
  options.bridges = cl.GetInt("bridges", 1, 64);
  options.ess_threshold = cl.GetDouble("ess-threshold", 0, 1);
  options.seed = static_cast<uint64_t>(cl.GetInt("seed", 0, 1 << 30));
  TerminalProgress progress(cl.Has("json"));
  options.progress = progress.Callback();
  const nlohmann::json result = RunRelightBench(options);
  if (cl.Has("json")) {
    std::cout << nlohmann::json{{"summary", result["summary"]},
                                {"equal_time", result["equal_time"]},
                                {"out", options.out_dir}}
                     .dump(2)
              << "\n";
    return 0;
  }
  std::printf("%-14s %11s %6s %12s %10s\n", "material", "sampler", "budget", "s/frame",
              "rel. RMSE");
  for (const auto& row : result["summary"]) {
    std::printf("%-14s %11s %6d %12.4f %10.4f\n", row["material"].get<std::string>().c_str(),
                row["sampler"].get<std::string>().c_str(), row["budget"].get<int>(),
                row["mean_frame_seconds"].get<double>(), row["mean_relative_rmse"].get<double>());
  }
  std::printf("\nequal time (at SIR's frame time):\n%-14s %10s %10s %10s %10s %12s\n",
              "material", "s/frame", "MIS", "SIR", "SMC", "SMC bridges");
  for (const auto& row : result["equal_time"]) {
    auto text = [](const nlohmann::json& v) {
      char b[32];
      if (v.is_number()) {
        std::snprintf(b, sizeof(b), "%.4f", v.get<double>());
      } else {
        std::snprintf(b, sizeof(b), "n/a");
      }
      return std::string(b);
    };
    std::printf("%-14s %10.4f %10s %10s %10s %12s\n", row["material"].get<std::string>().c_str(),
                row["frame_seconds"].get<double>(), text(row["mis_relative_rmse"]).c_str(),
                text(row["sir_relative_rmse"]).c_str(), text(row["smc_relative_rmse"]).c_str(),
                text(row["smc_bridges_relative_rmse"]).c_str());
  }
  std::printf("wrote %s/relight-bench.json, rmse-vs-time.png, frames-*.png\n",
              options.out_dir.c_str());
  return 0;
}

const CommandRegistration kPreviewBenchCommand(
    {"preview-bench", "MIS, SIR and SMC relighting on a turntable: error against time",
     RunPreviewBench});

}  // namespace
}  // namespace zbrdf::cli
