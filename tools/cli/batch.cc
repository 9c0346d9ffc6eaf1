// zbrdf batch merge|status|resubmit DIR: the reduce step and the bookkeeping of a batch folder
// (tools/batch.h, tools/slurm.h, docs/cluster.md).
#include <cstdio>
#include <iostream>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "tools/accuracy.h"
#include "tools/batch.h"
#include "tools/bench_run.h"
#include "tools/cli/command.h"
#include "tools/fit_all.h"
#include "tools/prior_build.h"
#include "tools/slurm.h"

namespace zbrdf::cli {
namespace {

// The shard count of the batch's last Slurm submission, else 1.
int RecordedShardCount(const std::string& dir) {
  const auto subs = SlurmSubmissions(dir);
  return subs.empty() ? 1 : subs.back().value("shard_count", 1);
}

int Merge(const std::string& dir, bool json) {
  const BatchManifest manifest = ReadManifest(dir);
  int rows = 0, failed = 0;
  if (manifest.command == "fit-all") {
    const FitAllSummary s = ReduceFitAll(dir);
    rows = static_cast<int>(s.table["rows"].size());
    failed = s.failed;
  } else if (manifest.command == "accuracy") {
    const AccuracySummary s = ReduceAccuracy(dir);
    rows = static_cast<int>(s.table["items"].size());
    for (const auto& item : s.table["items"]) failed += item.contains("failure");
  } else if (manifest.command == "bench") {
    const BenchSummary s = ReduceBench(dir);
    std::set<std::string> materials;
    for (const auto& row : s.table["rows"]) materials.insert(row.value("material", std::string()));
    rows = static_cast<int>(materials.size());
    failed = s.failed;
  } else if (manifest.command == "prior") {
    const BrdfPrior prior = ReducePriorBuild(dir);  // throws naming what is missing
    rows = prior.material_count();
    if (!json) {
      std::printf("prior: wrote %s (%d materials)\n",
                  manifest.options.value("out", std::string()).c_str(), rows);
    }
  } else {
    throw InputError(dir + "/manifest.json names the command '" + manifest.command +
                     "', which this zbrdf cannot merge (fit-all, accuracy, bench, prior)");
  }
  const int missing = static_cast<int>(manifest.items.size()) - rows;
  if (json) {
    std::cout << nlohmann::json{{"command", manifest.command}, {"items", manifest.items.size()},
                                {"merged", rows}, {"failed", failed}, {"missing", missing},
                                {"out", dir}}
                     .dump(2)
              << "\n";
  } else {
    std::printf("%s: merged %d of %zu items (%d failed) into %s\n", manifest.command.c_str(), rows,
                manifest.items.size(), failed, dir.c_str());
    if (missing > 0) {
      std::printf("  %d items have no result yet: zbrdf batch status %s; zbrdf batch resubmit %s\n",
                  missing, dir.c_str(), dir.c_str());
    }
  }
  return missing > 0 || failed > 0 ? 1 : 0;
}

int Status(const std::string& dir, bool json) {
  const BatchManifest manifest = ReadManifest(dir);
  const auto subs = SlurmSubmissions(dir);
  const std::vector<std::string> live = subs.empty() ? std::vector<std::string>() : LiveSlurmJobs(dir);
  const int shard_count = RecordedShardCount(dir);
  const auto status = BatchStatus(dir, shard_count, subs.empty() ? nullptr : &live);
  std::map<std::string, int> totals;
  std::map<int, std::map<std::string, int>> per_shard;
  for (const ItemStatus& s : status) {
    ++totals[ItemStateName(s.state)];
    ++per_shard[s.shard][ItemStateName(s.state)];
  }
  const std::vector<int> missing = ShardsWithMissingItems(status);
  if (json) {
    nlohmann::json items = nlohmann::json::array();
    for (const ItemStatus& s : status) {
      items.push_back({{"id", s.item.id}, {"shard", s.shard}, {"state", ItemStateName(s.state)}});
    }
    std::cout << nlohmann::json{{"command", manifest.command}, {"items", items},
                                {"totals", totals}, {"shard_count", shard_count},
                                {"shards_with_missing_items", missing}, {"slurm_jobs_live", live},
                                {"slurm_submissions", subs}}
                     .dump(2)
              << "\n";
    return 0;
  }
  std::printf("%s batch in %s: %zu items", manifest.command.c_str(), dir.c_str(), status.size());
  for (const char* state : {"done", "failed", "running", "stale", "pending"}) {
    if (totals.count(state)) std::printf(", %d %s", totals[state], state);
  }
  std::printf("\n");
  if (!subs.empty()) {
    const auto& last = subs.back();
    std::printf("  Slurm: array %s, merge %s (%d shards); %zu of its jobs/tasks still queued or running\n",
                last.value("array_job", std::string("?")).c_str(),
                last.value("merge_job", std::string("?")).c_str(), shard_count, live.size() / 2);
  }
  if (shard_count > 1) {
    for (const auto& [shard, counts] : per_shard) {
      std::printf("  shard %d:", shard);
      for (const auto& [state, n] : counts) std::printf(" %d %s", n, state.c_str());
      std::printf("\n");
    }
  }
  for (const ItemStatus& s : status) {
    if (s.state == ItemState::kRunning || s.state == ItemState::kStale) {
      std::printf("  %s %s (host %s, pid %ld)\n", ItemStateName(s.state), s.item.id.c_str(),
                  s.running.value("host", std::string("?")).c_str(), s.running.value("pid", 0L));
    }
  }
  if (!missing.empty()) {
    std::printf("  shards with items to do:");
    for (int m : missing) std::printf(" %d", m);
    std::printf(subs.empty() ? "  (rerun the command, or with --shard I/N)\n"
                             : "  (zbrdf batch resubmit %s)\n",
                dir.c_str());
  }
  return 0;
}

int Resubmit(const std::string& dir, bool json) {
  const BatchManifest manifest = ReadManifest(dir);
  const auto subs = SlurmSubmissions(dir);
  if (subs.empty()) {
    throw InputError(dir + " was not submitted to Slurm (no slurm/submissions.json); run its command "
                     "with --executor slurm, or locally again to finish it");
  }
  const nlohmann::json& last = subs.back();
  const int shard_count = last.value("shard_count", 1);
  const std::vector<std::string> live = LiveSlurmJobs(dir);
  const auto status = BatchStatus(dir, shard_count, &live);
  // Shards whose task is still queued or running finish on their own.
  std::vector<int> shards;
  for (int shard : ShardsWithMissingItems(status)) {
    bool queued = false;
    for (const auto& sub : subs) {
      const std::string task = sub.value("array_job", std::string()) + "_" + std::to_string(shard);
      queued = queued || std::find(live.begin(), live.end(), task) != live.end();
    }
    if (!queued) shards.push_back(shard);
  }
  if (shards.empty()) {
    if (json) {
      std::cout << nlohmann::json{{"resubmitted_shards", nlohmann::json::array()}}.dump(2) << "\n";
    } else {
      std::printf("nothing to resubmit: every item of %s has a result or a queued/running shard\n",
                  dir.c_str());
    }
    return 0;
  }
  const SlurmSite site = SlurmSite::FromJson(last.value("site", nlohmann::json::object()));
  const SlurmSubmission sub =
      SubmitSlurmBatch(dir, manifest, shard_count, shards, site, last.value("item_seconds", 60.0));
  if (json) {
    std::cout << nlohmann::json{{"resubmitted_shards", shards},
                                {"array_job", sub.array_job},
                                {"merge_job", sub.merge_job}}
                     .dump(2)
              << "\n";
  } else {
    std::printf("resubmitted %zu of %d shards as job array %s, merge job %s\n", shards.size(),
                shard_count, sub.array_job.c_str(), sub.merge_job.c_str());
  }
  return 0;
}

int RunBatch(const std::vector<std::string>& args) {
  CommandLine cl("batch",
                 "Bookkeeping of a batch folder (a fit-all, accuracy or bench --out DIR, a prior build's\n"
                 "--batch-dir; docs/cluster.md):\n"
                 "  merge DIR     build the command's tables and plots from the items' results\n"
                 "                (what an unsharded run writes; the Slurm merge job runs this)\n"
                 "  status DIR    items done, failed, running, stale (killed) and pending, per\n"
                 "                shard, with the Slurm jobs still queued\n"
                 "  resubmit DIR  submit again, as a job array, only the shards with items\n"
                 "                without a result (a killed or timed-out task), and a new merge");
  cl.Positional("ACTION", "merge, status or resubmit")
      .Positional("DIR", "the batch folder")
      .Flag("json", "print JSON")
      .Epilog("Examples:\n"
              "  zbrdf batch status results/merl-order8\n"
              "  zbrdf batch resubmit results/merl-order8\n"
              "  zbrdf batch merge results/merl-order8");
  if (!cl.Parse(args)) return 0;
  const std::string action = cl.Positional(0), dir = cl.Positional(1);
  const bool json = cl.Has("json");
  if (action == "merge") return Merge(dir, json);
  if (action == "status") return Status(dir, json);
  if (action == "resubmit") return Resubmit(dir, json);
  throw InputError("unknown batch action '" + action + "'; use merge, status or resubmit (zbrdf batch --help)");
}

const CommandRegistration kBatchCommand(
    {"batch",
     "merge, status and resubmit of a sharded batch (fit-all, accuracy, bench, prior build)",
     RunBatch});

}  // namespace
}  // namespace zbrdf::cli
