// `zbrdf bench`: capture strategies against ground truth, on the virtual rig (docs/bench.md).
//
// For each material, one virtual rig (its light transport is built once) runs every strategy:
// fixed plans (each order x each bracket size) and adaptive captures (acquisition/adaptive.h) with
// each order as the largest allowed. For each capture:
//   capture_time_s     on the rig's timing model (the virtual rig's clock: metering, projector
//                      settle, per frame max(frame period, exposure + readout))
//   processing_s       measured: HDR merge and zonal extraction; sh_s, fit_s the SH conversion
//                      and the D-BRDF fit (tools/sh_conversion.h, tools/fit_session.h)
//   coefficient_error  in-zone relative L2 of z_k(w_r) against the true coefficients up to the
//                      strategy's order (bands an adaptive capture did not take count as zero);
//                      coefficient_error_common the same up to the bench's largest order, the
//                      error comparable across strategies (the plot's)
//   sh_error_cosine_l2, sh_error_in_zone   the SH conversion against the material (cosine-
//                      weighted L2 over the full hemisphere, and over the zone)
//   dbrdf_error_cosine_l2   the D-BRDF fit against the material
//   ball_rmse          RMSE of a rendered ball (directional light) of the D-BRDF fit against the
//                      material's, relative to the RMS of the material's ball
//   renderable_error_cosine_l2, renderable_error_ngan, renderable_ball_rmse   the same for what
//                      a renderer gets: the prior fit `zbrdf fit` recommends by default, over the
//                      whole hemisphere (pooled and per-channel cosine-weighted L2), leave-one-out
//                      for the bundled prior's own materials
// An adaptive capture that kept no band above 1 (nothing glossy above its floor) skips the D-BRDF
// fit (its error and ball are then null): the processing it does not need.
// Before the materials the rig's systematic floor is measured on a Lambertian target
// (FloorProfile; DIR/floor.json), and adaptive captures use it.
// Results: DIR/bench.json ({"rows", "summary", "floor", ...}), DIR/bench.csv (one row per
// capture), DIR/bench.png (error against capture time per material, Pareto front drawn).
// Same options and seed: same errors (frames, truth and metrics are seeded, and no result depends
// on thread timing).
#pragma once

#include <atomic>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "acquisition/adaptive.h"
#include "basis/progress.h"
#include "tools/batch.h"

namespace zbrdf {

// 12 MERL materials from diffuse to mirror-like.
std::vector<std::string> DefaultBenchMaterials();

struct BenchStrategy {
  std::string name;  // "fixed-L8-x3", "adaptive-L8"
  bool adaptive = false;
  int order = 4;      // fixed: the order; adaptive: the largest order
  int exposures = 3;  // fixed: the bracket size (2 f-stops apart)
};

struct BenchOptions {
  std::string rig_path;
  std::string preset = "fast";
  std::string out_dir;
  std::vector<std::string> materials;  // empty: DefaultBenchMaterials()
  std::vector<int> orders{4, 6, 8, 10};
  std::vector<int> exposures{3, 1};  // bracket sizes of the fixed strategies
  bool adaptive = true;
  AdaptiveOptions adaptive_options;  // enabled is set per strategy
  bool measure_floor = true;         // the Lambertian floor capture (else no floor profile)
  uint64_t seed = 1;
  int truth_samples = 1024;  // GroundTruthOptions::samples
  bool fit = true;           // D-BRDF fits and balls
  bool renderable = true;    // the prior fit's whole-hemisphere error and ball (renderable_*)
  int ball_size = 64;
  int parallel_materials = 2;
  bool keep_frames = false;  // else each session's frames/ is deleted once processed
  Shard shard;               // the materials this process runs (default: all)
  std::vector<std::string> command_args;  // the command line, recorded in the manifest
  ProgressCallback progress;
  const std::atomic<bool>* interrupt = nullptr;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

std::vector<BenchStrategy> BenchStrategies(const BenchOptions& options);

struct BenchSummary {
  nlohmann::json table;  // what bench.json holds
  bool interrupted = false;
  int failed = 0;
};

// Throws InputError for bad options. A batch (tools/batch.h): one item per material (all its
// strategies), listed in DIR/manifest.json first; each material's rows go to
// DIR/items/<folder>.json (a rerun skips those materials) and the tables are rebuilt from them
// (ReduceBench). The floor capture is shared: DIR/floor.json is reused when it was measured for
// the same options, so shards (and `--executor slurm`, which measures it before submitting) do
// not repeat it. A shard writes no table.
BenchSummary RunBench(const BenchOptions& options);

// The batch's manifest for these options.
BatchManifest BenchManifest(const BenchOptions& options);

// Measures the floor into DIR/floor.json (or finds it there, measured for the same options);
// null when the options measure none. Interrupted: *interrupted is set and null returned.
nlohmann::json MeasureBenchFloor(const BenchOptions& options, bool* interrupted = nullptr);

// The reduce step: bench.json, bench.csv and the plots from DIR/items/ (the manifest's
// materials, in order) and DIR/floor.json. bench.json's wall_s is null (item_wall_s_sum holds
// the items' own wall times added up); a whole run sets it.
BenchSummary ReduceBench(const std::string& out_dir);

// Fixed (3 exposures by default: the thesis's) vs adaptive per order and material, from rows:
// {"pairs": [{material, order, fixed_time_s, adaptive_time_s, saving, fixed_error,
// adaptive_error, ...}], "mean_saving", "same_error_pairs", "target_met", "renderable_pairs",
// "same_renderable_error_pairs", "target_met_renderable"}. An adaptive capture has the "same
// error" when its coefficient error is at most the fixed one's times (1 + tolerance), and the
// "same renderable error" when both its renderable_error_cosine_l2 and renderable_ball_rmse are.
// The targets: mean saving >= 40% and every pair the same (renderable) error.
nlohmann::json CompareFixedAdaptive(const nlohmann::json& rows, int fixed_exposures = 3,
                                    double tolerance = 0.05);

// Error (the rows' `key`) against capture time, one panel per material, Pareto fronts drawn
// (OpenCV PNG), with `caption` under the panels.
void WriteBenchPlot(const nlohmann::json& rows, const std::string& path,
                    const std::string& key = "coefficient_error_common",
                    const std::string& caption = "in-zone coefficient error up to the largest "
                                                 "order (bands not taken count as zero)");

}  // namespace zbrdf
