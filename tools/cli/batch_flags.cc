#include "tools/cli/batch_flags.h"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <set>

#include <nlohmann/json.hpp>

#include "basis/error.h"

namespace zbrdf::cli {
namespace {

// The flags AddBatchFlags adds; all take a value.
const std::set<std::string>& BatchFlagNames() {
  static const std::set<std::string> names = {
      "shard", "executor", "shards", "slurm-config", "partition", "account",
      "setup", "sbatch",   "cpus-per-task", "mem", "time-limit"};
  return names;
}

}  // namespace

void AddBatchFlags(CommandLine& cl) {
  cl.Option("shard", "I/N", "run only shard I of N (items k with k % N == I); merge with `zbrdf batch merge DIR`")
      .Option("executor", "E", "local (run here) or slurm (submit a job array and a merge job)", "local")
      .Option("shards", "N", "slurm: tasks in the job array", "4")
      .Option("slurm-config", "FILE", "slurm: site settings (YAML: partition, account, setup, ...; docs/cluster.md)")
      .Option("partition", "NAME", "slurm: partition (overrides the site file)")
      .Option("account", "NAME", "slurm: account")
      .Option("setup", "CMD", "slurm: shell command run before zbrdf in each job, e.g. 'module load zbrdf'")
      .Option("sbatch", "LINES", "slurm: more #SBATCH options, separated by ';', e.g. '--qos=short'")
      .Option("cpus-per-task", "N", "slurm: CPUs per task (default 2)")
      .Option("mem", "SIZE", "slurm: memory per task, e.g. 4G (default 4G)")
      .Option("time-limit", "MIN", "slurm: time limit per task in minutes (default: from the item estimate)");
}

BatchRun ReadBatchFlags(const CommandLine& cl) {
  BatchRun run;
  const std::string executor = cl.Get("executor");
  if (executor != "local" && executor != "slurm") {
    throw InputError("--executor must be local or slurm (got '" + executor + "')");
  }
  run.slurm = executor == "slurm";
  if (cl.Has("shard")) {
    if (run.slurm) {
      throw InputError("--shard runs one shard here; with --executor slurm give --shards N instead");
    }
    run.shard = Shard::Parse(cl.Get("shard"));
  }
  run.shards = cl.GetInt("shards", 1, 10000);
  if (cl.Has("slurm-config")) run.site = SlurmSite::Load(cl.Get("slurm-config"));
  if (cl.Has("partition")) run.site.partition = cl.Get("partition");
  if (cl.Has("account")) run.site.account = cl.Get("account");
  if (cl.Has("setup")) run.site.setup = cl.Get("setup");
  if (cl.Has("sbatch")) {
    std::string lines = cl.Get("sbatch");
    size_t start = 0;
    while (start <= lines.size()) {
      size_t end = lines.find(';', start);
      if (end == std::string::npos) end = lines.size();
      std::string line = lines.substr(start, end - start);
      line.erase(0, line.find_first_not_of(" \t"));
      line.erase(line.find_last_not_of(" \t") + 1);
      if (!line.empty()) run.site.sbatch_lines.push_back(line);
      start = end + 1;
    }
  }
  if (cl.Has("cpus-per-task")) run.site.cpus_per_task = cl.GetInt("cpus-per-task", 1, 256);
  if (cl.Has("mem")) run.site.memory = cl.Get("mem");
  if (cl.Has("time-limit")) run.site.time_limit_minutes = cl.GetInt("time-limit", 1, 7 * 24 * 60);
  return run;
}

std::vector<std::string> ManifestArgs(const std::vector<std::string>& args) {
  std::vector<std::string> out;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    // --json shapes this process's own report (e.g. the job ids); shard logs are for people.
    if (a == "--json") continue;
    if (a.rfind("--", 0) == 0) {
      const size_t eq = a.find('=');
      const std::string name = a.substr(2, eq == std::string::npos ? std::string::npos : eq - 2);
      if (BatchFlagNames().count(name)) {
        if (eq == std::string::npos) ++i;  // its value
        continue;
      }
    }
    out.push_back(a);
  }
  return out;
}

int SubmitBatchToSlurm(const std::string& dir, const BatchManifest& manifest, const BatchRun& run,
                       double item_seconds, bool json) {
  const int shards = std::max(1, std::min<int>(run.shards, static_cast<int>(manifest.items.size())));
  const SlurmSubmission sub = SubmitSlurmBatch(dir, manifest, shards, {}, run.site, item_seconds);
  if (json) {
    std::cout << nlohmann::json{{"array_job", sub.array_job},
                                {"merge_job", sub.merge_job},
                                {"shards", shards},
                                {"items", manifest.items.size()},
                                {"time_limit_minutes", sub.time_limit_minutes},
                                {"out", dir}}
                     .dump(2)
              << "\n";
  } else {
    std::printf("%s: submitted %zu items as job array %s (%d shards, %d min each) and merge job %s\n"
                "  follow it: zbrdf batch status %s    (logs in %s/slurm/)\n",
                manifest.command.c_str(), manifest.items.size(), sub.array_job.c_str(), shards,
                sub.time_limit_minutes, sub.merge_job.c_str(), dir.c_str(), dir.c_str());
  }
  return 0;
}

}  // namespace zbrdf::cli
