// zbrdf bench: capture strategies (fixed orders and brackets, adaptive) against ground truth.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "basis/error.h"
#include "basis/parallel.h"
#include "tools/bench_run.h"
#include "tools/cli/batch_flags.h"
#include "tools/cli/command.h"
#include "tools/fit_all.h"
#include "tools/interrupt.h"
#include "tools/terminal_progress.h"

namespace zbrdf::cli {
namespace {

std::vector<int> IntList(const std::string& flag, const std::string& list) {
  std::vector<int> out;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item.empty()) continue;
    try {
      size_t used = 0;
      out.push_back(std::stoi(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InputError("--" + flag + ": '" + item + "' is not an integer (e.g. --" + flag +
                       " 4,8)");
    }
  }
  return out;
}

int RunBenchCommand(const std::vector<std::string>& args) {
  CommandLine cl(
      "bench",
      "Benchmarks capture strategies on the virtual rig against ground truth: for each\n"
      "material, fixed plans (each --orders x each --exposures bracket) and adaptive\n"
      "captures (docs/adaptive.md; each order as the largest allowed). Per capture: the\n"
      "capture time on the rig's timing model, the processing time (measured), and the\n"
      "errors (in-zone coefficient error; cosine-weighted L2 of the SH conversion and of\n"
      "the D-BRDF fit; rendered-ball RMSE). Writes DIR/bench.json, DIR/bench.csv and\n"
      "DIR/bench.png (error against capture time, Pareto front per material).");
  cl.Option("rig", "FILE", "rig description", "rig/rigs/thesis.yaml")
      .Option("preset", "P", "fast or full", "fast")
      .Option("materials", "LIST",
              "material specs separated by commas (default: 12 MERL materials "
              "from diffuse to mirror-like, listed in bench.json)")
      .Option("orders", "LIST", "orders of the strategies", "4,6,8,10")
      .Option("exposures", "LIST", "bracket sizes of the fixed strategies (2 f-stops apart)", "3,1")
      .Flag("no-adaptive", "fixed strategies only")
      .Option("error-target", "E",
              "adaptive: stop once the predicted relative error is below E "
              "(default: at the floor only)")
      .Flag("no-floor", "adaptive: do not measure the rig's floor on a Lambertian target first")
      .Flag("no-fit", "skip the D-BRDF fits and the balls")
      .Flag("no-renderable", "skip the prior fit's whole-hemisphere error (renderable_*)")
      .Option("out", "DIR", "folder for the sessions and the tables")
      .Option("seed", "N", "seed of every simulation", "1")
      .Option("truth-samples", "N", "samples per exitant point of the true coefficients", "1024")
      .Option("jobs", "N", "materials at once (default: min(2, worker threads))")
      .Flag("keep-frames", "keep each session's raw frames (default: deleted once processed)")
      .Flag("json", "print bench.json's summary as JSON");
  AddBatchFlags(cl);
  cl.Epilog(
          "Examples:\n"
          "  zbrdf bench --out results/bench            # default set, ~10 min on 2 cores\n"
          "  zbrdf bench --out results/bench --executor slurm --shards 12   # docs/cluster.md\n"
          "  zbrdf bench --materials merl:white-diffuse-bball,merl:chrome --orders 4,8 \\\n"
          "      --exposures 3 --out results/bench-small --json\n\n"
          "bench.json keys: rig, preset, seed, materials, orders, exposures, adaptive_options,\n"
          "truth_samples, floor (the Lambertian floor capture: band_energy, floor_profile), rows,\n"
          "summary, wall_s. Each row: material, strategy (fixed-L<order>-x<bracket> or\n"
          "adaptive-L<order>), adaptive, order, order_captured, exposures, patterns, frames,\n"
          "capture_time_s, processing_s, sh_s, fit_s, coefficient_error (at the row's order),\n"
          "coefficient_error_common (at the largest order: comparable across rows), "
          "sh_error_cosine_l2,\n"
          "sh_error_in_zone, dbrdf_error_cosine_l2, dbrdf_skipped, ball_rmse (relative to the\n"
          "true ball's RMS), renderable_error_cosine_l2, renderable_error_ngan and\n"
          "renderable_ball_rmse (the prior fit a renderer gets, whole hemisphere, leave-one-out),\n"
          "saturated_pixel_lobes, wall_s, and for adaptive rows "
          "adaptive_reason,\n"
          "adaptive_predicted_error, adaptive_isotropic, adaptive_bands; failure if it failed.\n"
          "summary: pairs (fixed x3 vs adaptive per material and order: times, errors, saving,\n"
          "same_error), mean_saving, same_error_pairs, tolerance, target_met (mean saving >= 40%\n"
          "with every adaptive error <= the fixed one x (1 + tolerance)), and the same for the\n"
          "renderable error: renderable_pairs, same_renderable_error_pairs,\n"
          "target_met_renderable. bench-renderable.png plots the renderable error. docs/bench.md.");
  if (!cl.Parse(args)) return 0;
  BenchOptions options;
  options.rig_path = cl.Get("rig");
  options.preset = cl.Get("preset");
  if (cl.Has("materials")) options.materials = ExpandMaterialList(cl.Get("materials"));
  options.orders = IntList("orders", cl.Get("orders"));
  options.exposures = IntList("exposures", cl.Get("exposures"));
  options.adaptive = !cl.Has("no-adaptive");
  if (cl.Has("error-target"))
    options.adaptive_options.error_target = cl.GetDouble("error-target", 0, 0.99);
  options.measure_floor = !cl.Has("no-floor");
  options.fit = !cl.Has("no-fit");
  options.renderable = !cl.Has("no-renderable");
  options.out_dir = cl.Get("out");
  options.seed = static_cast<uint64_t>(cl.GetInt("seed", 0, 1 << 30));
  options.truth_samples = cl.GetInt("truth-samples", 16, 1 << 20);  // BenchOptions::Validate
  options.parallel_materials =
      cl.Has("jobs") ? cl.GetInt("jobs", 1, 16) : std::min(2, WorkerThreads());
  options.keep_frames = cl.Has("keep-frames");
  const BatchRun batch = ReadBatchFlags(cl);
  options.shard = batch.shard;
  options.command_args = ManifestArgs(args);
  if (batch.slurm) {
    const BatchManifest manifest = BenchManifest(options);
    PrepareManifest(options.out_dir, manifest, Shard{});
    // The floor capture every shard needs, measured once here (a few seconds at the fast preset).
    MeasureBenchFloor(options);
    // Per material on 2 cores (docs/bench.md: the default set of 12, orders 4-10, takes about 10
    // minutes at the fast preset): 2 minutes, 4x that at full resolution.
    const double item_s = (options.preset == "full" ? 480.0 : 120.0) *
                          static_cast<double>(options.orders.size()) / 4.0;
    return SubmitBatchToSlurm(options.out_dir, manifest, batch, item_s, cl.Has("json"));
  }
  TerminalProgress progress(false);
  options.progress = progress.Callback();
  options.interrupt = InstallInterruptHandler();
  const BenchSummary summary = RunBench(options);
  if (!options.shard.IsWhole()) {
    std::printf("bench shard %s done (%d failed captures); the tables: zbrdf batch merge %s\n",
                options.shard.ToString().c_str(), summary.failed, options.out_dir.c_str());
    return summary.interrupted ? 130 : 0;
  }
  const nlohmann::json& s = summary.table.value("summary", nlohmann::json::object());
  if (cl.Has("json")) {
    nlohmann::json j = summary.table;
    j.erase("rows");
    j["failed"] = summary.failed;
    j["interrupted"] = summary.interrupted;
    std::cout << j.dump(2) << "\n";
  } else {
    std::printf("bench: %zu captures -> %s/bench.{json,csv,png}\n",
                summary.table.value("rows", nlohmann::json::array()).size(),
                options.out_dir.c_str());
    std::printf("  %-28s %5s %9s %9s %7s %9s %9s\n", "material", "order", "fixed s", "adapt s",
                "saving", "fixed err", "adapt err");
    for (const nlohmann::json& p : s.value("pairs", nlohmann::json::array())) {
      std::printf("  %-28s %5d %9.1f %9.1f %6.0f%% %9.4f %9.4f%s\n",
                  p["material"].get<std::string>().c_str(), p["order"].get<int>(),
                  p["fixed_time_s"].get<double>(), p["adaptive_time_s"].get<double>(),
                  100 * p["saving"].get<double>(), p["fixed_error"].get<double>(),
                  p["adaptive_error"].get<double>(),
                  p["same_error"].get<bool>() ? "" : "  (worse)");
    }
    if (s.contains("mean_saving")) {
      std::printf("  mean saving %.0f%%, same error in %d of %zu pairs: target %s\n",
                  100 * s["mean_saving"].get<double>(), s["same_error_pairs"].get<int>(),
                  s["pairs"].size(), s["target_met"].get<bool>() ? "met" : "not met");
      if (s.value("renderable_pairs", 0) > 0) {
        std::printf("  renderable error (prior fit, hemisphere and ball) no more than 5%% worse in "
                    "%d of %d pairs: target %s\n",
                    s["same_renderable_error_pairs"].get<int>(), s["renderable_pairs"].get<int>(),
                    s["target_met_renderable"].get<bool>() ? "met" : "not met");
      }
    }
  }
  if (summary.interrupted) {
    std::fprintf(stderr, "bench: interrupted; the tables hold what was finished.\n");
    return 130;
  }
  return summary.failed > 0 ? 1 : 0;
}

const CommandRegistration kBenchCommand({"bench",
                                         "benchmark capture strategies (fixed, adaptive) against "
                                         "ground truth: time vs error",
                                         RunBenchCommand});

}  // namespace
}  // namespace zbrdf::cli
