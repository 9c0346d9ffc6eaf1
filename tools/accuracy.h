// The accuracy benchmark (`zbrdf accuracy`, docs/accuracy.md): how good the renderable BRDF is
// over the whole hemisphere, on measured materials, with honest leave-one-out priors.
//
// For each rig, order and material (an "item"): the session DIR/sessions/<rig>-o<order>/<folder>
// is simulated (or reused when its zonal.exr exists; an interrupted one resumes), then
// `zbrdf fit --model auto` runs on it (tools/fit_session.h) with the prior built WITHOUT the
// material whenever the prior holds a material of that name (leave-one-out: the fit report's
// "excluded" lists it, and the item records it). Per item: the cosine-weighted L2 error of
// every candidate and of the recommended fit against the true material (Ngan et al. 2005's
// definition, per channel averaged, over the hemisphere and with both directions at theta <= 80
// deg; and pooled over channels), in the zone; the image error of the recommended fit (relative
// RMSE of a material ball under the built-in sky and under the studio map, against the true
// material's ball); the in-zone residual; the rig time (the virtual rig's clock); the fit time;
// and, for MERL materials, Ngan et al.'s best dense-data fit (data/baselines/).
//
// Each item's result is written atomically to DIR/items/<rig>-o<order>/<folder>.json, so a rerun
// skips finished items. The reduce step rewrites DIR/accuracy.json, accuracy.csv, accuracy.md
// (the tables of docs/accuracy.md), cdf-<rig>-o<order>-<device>.png (error CDF per method) and
// bars-<rig>-o<order>-<device>.png (per material) from whatever items exist.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "basis/progress.h"
#include "tools/batch.h"

namespace zbrdf {

struct AccuracyOptions {
  std::string out_dir;
  std::vector<std::string> rigs{"thesis"};  // names in rig/rigs/ or paths to rig files
  std::vector<int> orders{8};
  std::string preset = "fast";
  // Material specs; merl:* and rgl:* expand to the bundled sets.
  std::vector<std::string> materials{"merl:*", "rgl:*"};
  std::vector<std::string> candidates{"prior", "dbrdf", "ggx"};  // of --model auto
  std::string prior_path;            // empty: the bundled prior
  bool leave_one_out = true;
  bool images = true;
  int ball_size = 96, ball_spp = 64;
  uint64_t seed = 1;
  int parallel_items = 2;
  Shard shard;                            // the items this process runs (default: all)
  std::vector<std::string> command_args;  // the command line, recorded in the manifest
  ProgressCallback progress;
  const std::atomic<bool>* interrupt = nullptr;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct AccuracySummary {
  nlohmann::json table;  // accuracy.json: {"items": [...], "summary": [...]}
  int items = 0, computed = 0, reused = 0, failed = 0;
  bool interrupted = false;
};

// Throws InputError for bad options (an unreadable rig, no materials). A batch (tools/batch.h):
// DIR/manifest.json lists the items (rig x order x material) before any work; a shard
// (options.shard) runs only its items and leaves the reduce step to `zbrdf batch merge DIR`.
AccuracySummary RunAccuracy(const AccuracyOptions& options);

// The batch's manifest for these options (what RunAccuracy writes first).
BatchManifest AccuracyManifest(const AccuracyOptions& options);

// The reduce step alone: the tables and plots from the item files under out_dir (those of the
// manifest's items when DIR has a manifest, else every file under DIR/items/).
AccuracySummary ReduceAccuracy(const std::string& out_dir);

// "merl", "rgl" or "other": the device a material spec's data come from.
std::string MaterialDevice(const std::string& spec);

}  // namespace zbrdf
