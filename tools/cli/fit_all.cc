// zbrdf fit-all: simulate and fit many materials, and tabulate the models' errors.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "basis/parallel.h"
#include "tools/cli/batch_flags.h"
#include "tools/cli/command.h"
#include "tools/fit_all.h"
#include "tools/interrupt.h"
#include "tools/terminal_progress.h"

namespace zbrdf::cli {
namespace {

std::vector<std::string> SplitModels(const std::string& list) {
  std::vector<std::string> models;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!item.empty()) models.push_back(item);
  }
  if (models.empty()) throw InputError("--models is empty; e.g. --models dbrdf,ggx");
  return models;
}

int RunFitAllCommand(const std::vector<std::string>& args) {
  CommandLine cl("fit-all",
                 "Simulates every material on the rig and fits each model to it, writing a table\n"
                 "of the cosine-weighted L2 error (Ngan et al. 2005, full hemisphere, relative to\n"
                 "the true material) per material and model: DIR/fit-all.csv and DIR/fit-all.json\n"
                 "(with the median and worst error per model). Resumable: materials whose session\n"
                 "and fits exist in DIR are not redone; an interrupted one resumes. A batch\n"
                 "(docs/cluster.md): DIR/manifest.json lists one item per material; --shard I/N\n"
                 "runs a share of them, --executor slurm submits them as a job array.");
  cl.Option("rig", "FILE", "rig description, e.g. rig/rigs/thesis.yaml")
      .Option("materials", "LIST", "material specs separated by commas; merl:* = all bundled", "merl:*")
      .Option("order", "L", "zonal order", "8")
      .Option("out", "DIR", "folder for the sessions and the table")
      .Option("preset", "P", "fast or full", "fast")
      .Option("models", "LIST", "models to fit: dbrdf, ggx, ward, as", "dbrdf,ggx")
      .Option("seed", "N", "seed of every simulation", "1")
      .Option("jobs", "N", "materials processed at once (default: the worker threads)")
      .Flag("refit", "fit again even where fit-<model>.json exists")
      .Flag("json", "print the table summary as JSON");
  AddBatchFlags(cl);
  cl.Epilog("Examples:\n"
            "  zbrdf fit-all --rig rig/rigs/thesis.yaml --materials 'merl:*' --order 8 \\\n"
            "      --out results/merl-order8 --preset fast --models dbrdf,ggx\n"
            "  zbrdf fit-all --rig rig/rigs/thesis.yaml --out results/merl-order8 \\\n"
            "      --executor slurm --shards 20 --partition short    # then: zbrdf batch status DIR");
  if (!cl.Parse(args)) return 0;
  FitAllOptions options;
  options.rig_path = cl.Get("rig");
  options.preset = cl.Get("preset");
  options.order = cl.GetInt("order", 0, 30);
  options.out_dir = cl.Get("out");
  options.materials = ExpandMaterialList(cl.Get("materials"));
  options.models = SplitModels(cl.Get("models"));
  options.seed = static_cast<uint64_t>(cl.GetInt("seed", 0, 1 << 30));
  options.parallel_materials = cl.Has("jobs") ? cl.GetInt("jobs", 1, 16) : std::min(2, WorkerThreads());
  options.refit = cl.Has("refit");
  const BatchRun run = ReadBatchFlags(cl);
  options.shard = run.shard;
  options.command_args = ManifestArgs(args);
  if (run.slurm) {
    const BatchManifest manifest = FitAllManifest(options);
    PrepareManifest(options.out_dir, manifest, Shard{});
    // Per item on 2 cores (docs/cluster.md): a fast-preset simulation takes 5 s at order 4 and
    // 17-70 s at order 8, a full one about 4x that (cold caches); each model's fit 5-30 s.
    const double simulate_s = (options.preset == "full" ? 280.0 : 70.0) *
                              std::max(0.25, (options.order + 1.0) * (options.order + 1.0) / 81.0);
    const double item_s = simulate_s + 30.0 * static_cast<double>(options.models.size());
    return SubmitBatchToSlurm(options.out_dir, manifest, run, item_s, cl.Has("json"));
  }
  TerminalProgress progress(false);
  options.progress = progress.Callback();
  options.interrupt = InstallInterruptHandler();
  const FitAllSummary summary = RunFitAll(options);
  if (!options.shard.IsWhole()) {
    if (cl.Has("json")) {
      std::cout << nlohmann::json{{"shard", options.shard.ToString()}, {"items", summary.items},
                                  {"reused_items", summary.reused_items},
                                  {"simulated", summary.simulated}, {"fitted", summary.fitted},
                                  {"failed", summary.failed}, {"interrupted", summary.interrupted}}
                       .dump(2)
                << "\n";
    } else {
      std::printf("fit-all shard %s: %d materials (%d already done, %d simulated, %d fits, %d "
                  "failed); the table: zbrdf batch merge %s\n",
                  options.shard.ToString().c_str(), summary.items, summary.reused_items,
                  summary.simulated, summary.fitted, summary.failed, options.out_dir.c_str());
    }
    if (summary.interrupted) {
      std::fprintf(stderr, "fit-all: interrupted; run the same command again to continue.\n");
      return 130;
    }
    return 0;  // failed items are results too: the merge reports them
  }
  if (cl.Has("json")) {
    nlohmann::json j = summary.table;
    j.erase("rows");
    j["simulated"] = summary.simulated;
    j["reused_sessions"] = summary.reused_sessions;
    j["fitted"] = summary.fitted;
    j["reused_fits"] = summary.reused_fits;
    j["reused_items"] = summary.reused_items;
    j["failed"] = summary.failed;
    j["interrupted"] = summary.interrupted;
    std::cout << j.dump(2) << "\n";
  } else {
    std::printf("fit-all: %zu materials (%d simulated, %d sessions reused; %d fits, %d reused; %d "
                "rows reused; %d failed) -> %s/fit-all.csv\n",
                summary.table["rows"].size(), summary.simulated, summary.reused_sessions,
                summary.fitted, summary.reused_fits, summary.reused_items, summary.failed,
                options.out_dir.c_str());
    for (const auto& [model, s] : summary.table["summary"].items()) {
      if (s["median_error_cosine_l2"].is_null()) continue;
      std::printf("  %-6s median error %.2f%%, worst %.2f%% (%s), %d materials\n", model.c_str(),
                  100 * s["median_error_cosine_l2"].get<double>(),
                  100 * s["worst_error_cosine_l2"].get<double>(),
                  s["worst_material"].get<std::string>().c_str(), s["materials"].get<int>());
    }
  }
  if (summary.interrupted) {
    std::fprintf(stderr, "fit-all: interrupted; run the same command again to continue.\n");
    return 130;
  }
  return summary.failed > 0 ? 1 : 0;
}

const CommandRegistration kFitAllCommand({"fit-all",
                                          "simulate and fit many materials; table of model errors",
                                          RunFitAllCommand});

}  // namespace
}  // namespace zbrdf::cli
