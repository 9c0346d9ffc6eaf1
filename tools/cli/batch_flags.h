// Flags shared by the batch commands (fit-all, accuracy): which shard to run, and how to hand the
// whole batch to Slurm (tools/batch.h, tools/slurm.h, docs/cluster.md).
#pragma once

#include <string>
#include <vector>

#include "tools/batch.h"
#include "tools/cli/command.h"
#include "tools/slurm.h"

namespace zbrdf::cli {

// --shard I/N, --executor local|slurm, --shards N, and the Slurm site's flags (--slurm-config,
// --partition, --account, --setup, --sbatch, --cpus-per-task, --mem, --time-limit).
void AddBatchFlags(CommandLine& cl);

struct BatchRun {
  Shard shard;         // local: the items this process runs
  bool slurm = false;  // --executor slurm: submit instead of running
  int shards = 4;      // slurm: tasks in the array
  SlurmSite site;
};
// Throws InputError for a bad value, or for --shard with --executor slurm.
BatchRun ReadBatchFlags(const CommandLine& cl);

// The command's arguments without the flags AddBatchFlags adds and without --json: what each
// shard reruns (its log is for people).
std::vector<std::string> ManifestArgs(const std::vector<std::string>& args);

// Submits the batch in dir (its manifest written) to Slurm and prints the job ids (or, with
// json, one JSON object). Returns the exit status.
int SubmitBatchToSlurm(const std::string& dir, const BatchManifest& manifest, const BatchRun& run,
                       double item_seconds, bool json);

}  // namespace zbrdf::cli
