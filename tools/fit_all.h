// Batch simulation and fitting of many materials (`zbrdf fit-all`): the table behind the model
// comparison in docs/fitting.md.
//
// A batch (tools/batch.h): one work item per material, listed in DIR/manifest.json before any
// work. For each material: a session DIR/<name>/ is simulated on the rig (tools/virtual_capture.h;
// resumed if a previous run was interrupted, skipped if its zonal.exr exists), then each model is
// fitted (tools/fit_session.h) unless DIR/<name>/fit-<model>.json already holds a result; the
// item's row is written to DIR/items/<name>.json, and a rerun skips materials whose row exists.
// Two materials run at a time (each stage is itself mostly single-threaded), so both cores work.
// The table DIR/fit-all.csv (one row per material, error_cosine_l2 per model) and
// DIR/fit-all.json (the rows plus the median and worst error per model) are built from the rows
// (ReduceFitAll) after every material, so an interrupted batch leaves a valid table. A shard
// (options.shard, e.g. one task of a Slurm array) runs only its items and writes no table: the
// reduce step (`zbrdf batch merge DIR`) does, with the same numbers as an unsharded run.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "basis/progress.h"
#include "tools/batch.h"

namespace zbrdf {

// "merl:*" and "rgl:*" expand to every material of that bundled set; other specs are kept. Specs are separated
// by commas; a comma starts a new spec only when the next token names a model ("x:" before any
// '='), so "ggx:alpha=0.2,F0=0.5,lambert:0.5" is two specs.
std::vector<std::string> ExpandMaterialList(const std::string& list);

// A folder name for a material spec: "merl:blue-acrylic" -> "merl-blue-acrylic".
std::string MaterialFolderName(const std::string& spec);

// Appends one batch item per material spec, in order: id id_prefix + its folder name, result
// "items/" + result_folder + folder + ".json". Throws InputError naming a spec listed twice (or
// two specs that share a folder name).
void AddMaterialItems(const std::vector<std::string>& specs, const std::string& id_prefix,
                      const std::string& result_folder, BatchManifest* manifest);

struct FitAllOptions {
  std::string rig_path;
  std::string preset = "fast";
  int order = 8;
  std::string out_dir;
  std::vector<std::string> materials;
  std::vector<std::string> models{"dbrdf", "ggx"};
  uint64_t seed = 1;
  int parallel_materials = 2;   // materials in flight
  bool refit = false;           // fit again even where fit-<model>.json exists
  Shard shard;                  // the items this process runs (default: all)
  std::vector<std::string> command_args;  // the command line, recorded in the manifest
  ProgressCallback progress;
  const std::atomic<bool>* interrupt = nullptr;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct FitAllSummary {
  nlohmann::json table;          // {"rows": [...], "summary": {model: {median, worst, ...}}}
  int simulated = 0, reused_sessions = 0, fitted = 0, reused_fits = 0, failed = 0;
  int items = 0, reused_items = 0;  // items this process owns; of them, rows found in DIR/items/
  bool interrupted = false;
};

// Throws InputError for bad options (unknown model, no materials, unreadable rig).
FitAllSummary RunFitAll(const FitAllOptions& options);

// The batch's manifest for these options (what RunFitAll writes first).
BatchManifest FitAllManifest(const FitAllOptions& options);

// The reduce step: DIR/fit-all.csv and fit-all.json from the rows in DIR/items/ of the
// manifest's materials, in the manifest's order (rows not yet there are left out). Returns the
// table; failed counts rows with a failure.
FitAllSummary ReduceFitAll(const std::string& out_dir);

}  // namespace zbrdf
