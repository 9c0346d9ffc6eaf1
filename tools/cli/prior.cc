// zbrdf prior: build and inspect the measured-material priors `zbrdf fit --model prior` uses.
#include <cstdio>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <set>

#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "brdf/brdf_file.h"
#include "brdf/brdf_prior.h"
#include "brdf/material_spec.h"
#include "brdf/nbrdf.h"
#include "tools/cli/batch_flags.h"
#include "tools/cli/command.h"
#include "tools/prior_build.h"
#include "tools/terminal_progress.h"

namespace zbrdf::cli {
namespace {

namespace fs = std::filesystem;

int RunBuild(const std::vector<std::string>& args) {
  CommandLine cl("prior build",
                 "Builds a prior from measured materials: each is tabulated on a half/difference\n"
                 "grid (sqrt-spaced theta_h), made bilaterally symmetric and reciprocal, and\n"
                 "stored in HALF precision (docs/prior.md). The default prior shipped in\n"
                 "data/priors/merl100.exr is `zbrdf prior build --from 'merl:*'`.");
  cl.Option("from", "LIST",
            "comma-separated: merl:* or rgl:* (bundled sets), material specs, MERL .binary, "
            "network .json or RGL .bsdf files, or folders of them")
      .Option("out", "FILE.exr", "the prior file to write")
      .Option("exclude", "NAMES", "materials to leave out, comma-separated")
      .Option("grid", "NH,ND,NP", "node counts in theta_h, theta_d, phi_d", "32,32,16")
      .Option("batch-dir", "DIR", "with --shard or --executor slurm: the batch folder (default: FILE.exr.batch)")
      .Flag("json", "print a JSON summary");
  AddBatchFlags(cl);
  cl.Epilog("Examples:\n"
              "  zbrdf prior build --from 'merl:*' --out data/priors/merl100.exr\n"
              "  zbrdf prior build --from 'merl:*,rgl:*' --out merl-rgl.exr\n"
              "  zbrdf prior build --from ~/brdfs/merl-binary/ --out lab.exr\n"
              "  zbrdf prior build --from /shared/brdfs/ --out /shared/lab.exr --executor slurm --shards 40\n"
              "A batch (--shard I/N, --executor slurm; docs/cluster.md) tabulates one material per\n"
              "item into the batch folder; `zbrdf batch merge DIR` writes the prior file.");
  if (!cl.Parse(args)) return 0;
  if (!cl.Has("from") || !cl.Has("out")) throw InputError("prior build needs --from and --out (see --help)");
  const std::vector<double> dims = cl.GetDoubles("grid", 3);
  for (double d : dims) {
    if (d != std::floor(d)) throw InputError("--grid needs three whole node counts (got " + cl.Get("grid") + ")");
  }
  const HalfDiffGrid grid(static_cast<int>(dims[0]), static_cast<int>(dims[1]), static_cast<int>(dims[2]));
  PriorBuildOptions build;
  build.from = cl.GetList("from");
  if (cl.Has("exclude")) build.exclude = cl.GetList("exclude");
  build.grid = grid;
  build.out = cl.Get("out");
  if (cl.Has("batch-dir")) build.batch_dir = cl.Get("batch-dir");
  const BatchRun batch = ReadBatchFlags(cl);
  build.shard = batch.shard;
  build.command_args = ManifestArgs(args);
  build.command_args.insert(build.command_args.begin(), "build");
  if (batch.slurm || !batch.shard.IsWhole()) {
    if (batch.slurm) {
      const BatchManifest manifest = PriorBuildManifest(build);
      PrepareManifest(build.BatchDir(), manifest, Shard{});
      // A material's tabulation: about 1 s for a network, 10 s for a 33 MB MERL table read from
      // a shared file system.
      return SubmitBatchToSlurm(build.BatchDir(), manifest, batch, 10.0, cl.Has("json"));
    }
    TerminalProgress bar(cl.Has("json"));
    build.progress = bar.Callback();
    const int tabulated = RunPriorBuildShard(build);
    std::printf("prior build shard %s: %d materials tabulated into %s; the prior: zbrdf batch merge %s\n",
                build.shard.ToString().c_str(), tabulated, build.BatchDir().c_str(),
                build.BatchDir().c_str());
    return 0;
  }
  std::vector<PriorSource> sources;
  for (const PriorSourceRef& ref : CollectPriorSources(build.from, build.exclude)) {
    sources.push_back(LoadPriorSource(ref));
  }
  TerminalProgress bar(cl.Has("json"));
  BrdfPrior prior = BuildPrior(sources, grid, bar.Callback());
  nlohmann::json from = nlohmann::json::array();
  for (const std::string& item : cl.GetList("from")) from.push_back(item);
  prior.info["from"] = from;
  const std::string out = cl.Get("out");
  if (fs::path(out).has_parent_path()) fs::create_directories(fs::path(out).parent_path());
  WritePriorFile(out, prior);
  const nlohmann::json summary = {{"prior", out},
                                  {"materials", prior.material_count()},
                                  {"grid", grid.ToString()},
                                  {"bytes", static_cast<long long>(fs::file_size(out))}};
  if (cl.Has("json")) {
    std::cout << summary.dump(2) << "\n";
  } else {
    std::printf("wrote %s: %d materials on a %s grid, %.1f MB\n", out.c_str(),
                prior.material_count(), grid.ToString().c_str(), fs::file_size(out) / 1e6);
  }
  return 0;
}

int RunInfo(const std::vector<std::string>& args) {
  CommandLine cl("prior info", "Lists a prior's materials, grid and provenance.");
  cl.Positional("FILE", "prior file (default: the bundled one)", false).Flag("json", "print JSON");
  if (!cl.Parse(args)) return 0;
  const std::string path = cl.NumPositionals() > 0 ? cl.Positional(0) : DefaultPriorPath();
  const BrdfPrior prior = ReadPriorFile(path);
  nlohmann::json j = {{"prior", path},
                      {"grid", prior.grid.ToString()},
                      {"materials", prior.materials},
                      {"info", prior.info}};
  if (cl.Has("json")) {
    std::cout << j.dump(2) << "\n";
  } else {
    std::printf("%s: %d materials on a %s grid\n", path.c_str(), prior.material_count(),
                prior.grid.ToString().c_str());
    for (size_t k = 0; k < prior.materials.size(); ++k) {
      std::printf("  %-30s %s\n", prior.materials[k].c_str(), prior.sources[k].c_str());
    }
  }
  return 0;
}

int RunPrior(const std::vector<std::string>& args) {
  const std::string usage =
      "Usage: zbrdf prior build|info [options]\n\n"
      "  build  build a prior from measured materials (zbrdf prior build --help)\n"
      "  info   list a prior's materials (zbrdf prior info --help)\n";
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::cout << usage;
    return args.empty() ? 2 : 0;
  }
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (args[0] == "build") return RunBuild(rest);
  if (args[0] == "info") return RunInfo(rest);
  throw InputError("zbrdf prior: unknown action '" + args[0] + "'; use build or info");
}

const CommandRegistration kPriorCommand(
    {"prior",
     "build or inspect a measured-material prior (fit --model prior)",
     RunPrior,
     {{"build", "build a prior from measured materials"}, {"info", "list a prior's materials"}}});

}  // namespace
}  // namespace zbrdf::cli
