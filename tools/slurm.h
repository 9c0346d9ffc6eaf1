// Slurm as the executor of a batch (docs/cluster.md): zbrdf describes the work, Slurm schedules it.
//
// A batch folder (tools/batch.h) is submitted as one job array of N shards, task I running
//   zbrdf <command> <the same flags> --shard I/N
// and a merge job (`zbrdf batch merge DIR`) that starts when every task has succeeded
// (--dependency=afterok, --kill-on-invalid-dep=yes). The scripts are written to DIR/slurm/
// (shards.sh, merge.sh; task logs shard-<I>.out, merge-<job>.out) and every submission is
// recorded in DIR/slurm/submissions.json, which `zbrdf batch status` and `zbrdf batch resubmit`
// read. Jobs run in the folder the batch was submitted from (--chdir) with the submitting shell's
// environment (sbatch's default --export=ALL), so ZBRDF_CACHE_DIR and relative paths carry over.
// Client commands (sbatch, squeue) are found on PATH and read SLURM_CONF as usual.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tools/batch.h"

namespace zbrdf {

// Site settings: from a small YAML file (--slurm-config) and flags that override it.
//   partition: short            # sbatch --partition
//   account: vision-lab         # sbatch --account
//   setup: module load zbrdf    # shell lines run before zbrdf in every job (puts it on PATH)
//   zbrdf: /opt/zbrdf/bin/zbrdf # the binary jobs run (default: this zbrdf's absolute path)
//   cpus_per_task: 2
//   memory: 4G                  # sbatch --mem (per task)
//   time_limit_minutes: 0       # 0: 3x the per-item estimate x items per shard + 5 min
//   sbatch: ["--qos=normal"]    # more #SBATCH lines
struct SlurmSite {
  std::string partition, account, setup, zbrdf;
  std::vector<std::string> sbatch_lines;
  int cpus_per_task = 2;
  std::string memory = "4G";
  int time_limit_minutes = 0;

  // Throws InputError naming the file and key on an unreadable file or a bad value.
  static SlurmSite Load(const std::string& yaml_path);
  nlohmann::json ToJson() const;
  static SlurmSite FromJson(const nlohmann::json& j);
};

struct SlurmSubmission {
  std::string array_job, merge_job;  // job ids
  int shard_count = 0;
  std::vector<int> shards;  // the array's task ids
  int time_limit_minutes = 0;
};

// Writes DIR/slurm/shards.sh and merge.sh for the manifest (DIR must hold it: PrepareManifest)
// and submits the array (the given shards, or all of 0..shard_count-1 when empty) and the merge
// job. item_seconds: the expected time of one item on cpus_per_task cores (sets the time limit
// unless the site fixes one). Throws DeviceError when sbatch is missing or refuses, with its
// message.
SlurmSubmission SubmitSlurmBatch(const std::string& dir, const BatchManifest& manifest,
                                 int shard_count, const std::vector<int>& shards,
                                 const SlurmSite& site, double item_seconds);

// The submissions recorded in DIR/slurm/submissions.json, oldest first (empty if none).
std::vector<nlohmann::json> SlurmSubmissions(const std::string& dir);

// The job ids ("123", "123_4") that squeue still lists among the batch's submissions (pending or
// running); empty when squeue is missing or fails.
std::vector<std::string> LiveSlurmJobs(const std::string& dir);

// The time limit, in whole minutes, for shards of items_per_shard items of item_seconds each.
int SlurmTimeLimitMinutes(double item_seconds, int items_per_shard);

// Quotes a word for a POSIX shell ('...' with ' escaped).
std::string ShellQuote(const std::string& word);

}  // namespace zbrdf
