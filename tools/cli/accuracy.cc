// zbrdf accuracy: the whole-hemisphere accuracy benchmark of the renderable fits
// (tools/accuracy.h, docs/accuracy.md).
#include <algorithm>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "tools/accuracy.h"
#include "tools/cli/batch_flags.h"
#include "tools/cli/command.h"
#include "tools/interrupt.h"
#include "tools/terminal_progress.h"

namespace zbrdf::cli {
namespace {

int RunAccuracyCommand(const std::vector<std::string>& args) {
  CommandLine cl(
      "accuracy",
      "How accurate the renderable BRDF is over the whole hemisphere (docs/accuracy.md). For\n"
      "every rig, order and material: simulates the capture (or reuses DIR/sessions/...),\n"
      "runs `zbrdf fit --model auto` with the prior built without the material (leave-one-\n"
      "out), and measures every candidate against the true material: cosine-weighted L2 over\n"
      "the hemisphere and at theta <= 80 deg (Ngan et al. 2005, per channel averaged; pooled\n"
      "too), in the zone, the material ball's image error under the sky and a studio map, the\n"
      "in-zone residual, rig and fit time; beside Ngan et al.'s dense-data fits for MERL.\n"
      "MERL materials (merl:*) are left out of the prior one at a time; the RGL validation\n"
      "set (rgl:*, another device) is fitted with the prior learned from all of MERL.\n"
      "Writes DIR/accuracy.json, accuracy.csv, accuracy.md, cdf-*.png, bars-*.png and one\n"
      "file per item in DIR/items/ (a rerun skips finished items; Ctrl-C keeps them).");
  cl.Option("out", "DIR", "output folder")
      .Option("rigs", "LIST", "rig names (rig/rigs/NAME.yaml) or files", "thesis")
      .Option("orders", "LIST", "zonal orders", "8")
      .Option("preset", "P", "fast or full", "fast")
      .Option("materials", "LIST", "material specs; merl:* and rgl:* expand", "merl:*,rgl:*")
      .Option("candidates", "LIST", "models --model auto compares", "prior,dbrdf,ggx")
      .Option("prior", "FILE", "prior file (default: data/priors/merl100.exr)")
      .Flag("no-leave-one-out", "let each material's own data stay in the prior (an upper bound)")
      .Flag("no-images", "skip the material-ball image errors")
      .Option("ball", "SIZE,SPP", "ball image size and samples per pixel", "96,64")
      .Option("seed", "N", "seed of every simulation", "1")
      .Option("jobs", "N", "items in flight at once", "2")
      .Flag("reduce-only", "only rebuild the tables and plots from DIR/items/")
      .Flag("json", "print the summary as JSON");
  AddBatchFlags(cl);
  cl.Epilog("Examples:\n"
              "  zbrdf accuracy --out results/accuracy                   # order 8, thesis rig\n"
              "  zbrdf accuracy --out results/accuracy --orders 4,6,8,10 --rigs thesis,full-dome\n"
              "  zbrdf accuracy --out /tmp/a --materials merl:blue-acrylic,rgl:cardboard\n"
              "  zbrdf accuracy --out results/accuracy --executor slurm --shards 50  # docs/cluster.md");
  if (!cl.Parse(args)) return 0;
  if (!cl.Has("out")) throw InputError("accuracy needs --out DIR (see --help)");
  AccuracySummary summary;
  if (cl.Has("reduce-only")) {
    summary = ReduceAccuracy(cl.Get("out"));
  } else {
    AccuracyOptions o;
    o.out_dir = cl.Get("out");
    o.rigs = cl.GetList("rigs");
    o.orders.clear();
    for (const std::string& s : cl.GetList("orders")) {
      char* end = nullptr;
      const long v = std::strtol(s.c_str(), &end, 10);
      if (end == s.c_str() || *end != '\0') throw InputError("--orders needs whole numbers (got '" + s + "')");
      o.orders.push_back(static_cast<int>(v));
    }
    o.preset = cl.Get("preset");
    o.materials = {cl.Get("materials")};
    o.candidates = cl.GetList("candidates");
    if (cl.Has("prior")) o.prior_path = cl.Get("prior");
    o.leave_one_out = !cl.Has("no-leave-one-out");
    o.images = !cl.Has("no-images");
    const std::vector<double> ball = cl.GetDoubles("ball", 2);
    o.ball_size = static_cast<int>(ball[0]);
    o.ball_spp = static_cast<int>(ball[1]);
    o.seed = static_cast<uint64_t>(cl.GetInt("seed", 0, 1 << 30));
    o.parallel_items = cl.GetInt("jobs", 1, 16);
    const BatchRun run = ReadBatchFlags(cl);
    o.shard = run.shard;
    o.command_args = ManifestArgs(args);
    if (run.slurm) {
      const BatchManifest manifest = AccuracyManifest(o);
      PrepareManifest(o.out_dir, manifest, Shard{});
      // Per item on 2 cores (docs/accuracy.md): simulation as in fit-all, then --model auto's
      // candidates with cross-validation and two material balls: about 3 minutes at order 8.
      const int order = *std::max_element(o.orders.begin(), o.orders.end());
      const double item_s = (o.preset == "full" ? 400.0 : 180.0) *
                            std::max(0.25, (order + 1.0) * (order + 1.0) / 81.0);
      return SubmitBatchToSlurm(o.out_dir, manifest, run, item_s, cl.Has("json"));
    }
    TerminalProgress progress(cl.Has("json"));
    o.progress = progress.Callback();
    o.interrupt = InstallInterruptHandler();
    summary = RunAccuracy(o);
    if (!o.shard.IsWhole()) {
      std::printf("accuracy shard %s: %d items (%d computed, %d already done, %d failed); the "
                  "tables: zbrdf batch merge %s\n",
                  o.shard.ToString().c_str(), summary.items, summary.computed, summary.reused,
                  summary.failed, o.out_dir.c_str());
      return summary.interrupted ? 130 : 0;
    }
  }
  if (cl.Has("json")) {
    nlohmann::json j = {{"summary", summary.table["summary"]},
                        {"items", summary.items},
                        {"computed", summary.computed},
                        {"reused", summary.reused},
                        {"failed", summary.failed},
                        {"interrupted", summary.interrupted},
                        {"out", cl.Get("out")}};
    std::cout << j.dump(2) << "\n";
  } else {
    for (const auto& s : summary.table["summary"]) {
      const auto& rec = s["methods"]["recommended"];
      auto f = [](const nlohmann::json& v) { return v.is_number() ? v.get<double>() : NAN; };
      std::printf("%s order %d %s: %d materials, recommended median %.3f (hemisphere) / %.3f "
                  "(theta <= 80); above 1.0: %d; below Ngan: %d of %d\n",
                  s["rig"].get<std::string>().c_str(), s["order"].get<int>(),
                  s["device"].get<std::string>().c_str(), s["materials"].get<int>(),
                  f(rec["median_hemisphere"]), f(rec["median_theta_80"]),
                  s["recommended_above_1"].get<int>(), s["below_ngan"].get<int>(),
                  s["with_ngan"].get<int>());
    }
    std::printf("wrote %s/accuracy.md, accuracy.json, accuracy.csv and plots\n", cl.Get("out").c_str());
  }
  return summary.interrupted ? 130 : 0;
}

const CommandRegistration kAccuracyCommand(
    {"accuracy", "whole-hemisphere accuracy benchmark (leave-one-out, MERL and RGL)",
     RunAccuracyCommand});

}  // namespace
}  // namespace zbrdf::cli
