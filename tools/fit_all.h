// Batch simulation and fitting of many materials (`zbrdf fit-all`): the table behind the model
// comparison in docs/fitting.md.
//
// For each material: a session DIR/<name>/ is simulated on the rig (tools/virtual_capture.h;
// resumed if a previous run was interrupted, skipped if its zonal.exr exists), then each model is
// fitted (tools/fit_session.h) unless DIR/<name>/fit-<model>.json already holds a result. Two
// materials run at a time (each stage is itself mostly single-threaded), so both cores work.
// The table DIR/fit-all.csv (one row per material, error_cosine_l2 per model) and
// DIR/fit-all.json (the rows plus the median and worst error per model) are rewritten after
// every material, so an interrupted batch leaves a valid table.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "basis/progress.h"

namespace zbrdf {

// "merl:*" and "rgl:*" expand to every material of that bundled set; other specs are kept. Specs are separated
// by commas; a comma starts a new spec only when the next token names a model ("x:" before any
// '='), so "ggx:alpha=0.2,F0=0.5,lambert:0.5" is two specs.
std::vector<std::string> ExpandMaterialList(const std::string& list);

// A folder name for a material spec: "merl:blue-acrylic" -> "merl-blue-acrylic".
std::string MaterialFolderName(const std::string& spec);

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
  ProgressCallback progress;
  const std::atomic<bool>* interrupt = nullptr;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct FitAllSummary {
  nlohmann::json table;          // {"rows": [...], "summary": {model: {median, worst, ...}}}
  int simulated = 0, reused_sessions = 0, fitted = 0, reused_fits = 0, failed = 0;
  bool interrupted = false;
};

// Throws InputError for bad options (unknown model, no materials, unreadable rig).
FitAllSummary RunFitAll(const FitAllOptions& options);

}  // namespace zbrdf
