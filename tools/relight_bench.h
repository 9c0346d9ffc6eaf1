// `zbrdf preview-bench`: MIS, SIR, SMC and SMC bridges on a turntable, error against time (docs/preview.md,
// "Relighting: measured").
//
// For each material, a turntable of `frames` frames (the environment turned by 360 / frames deg
// per frame about the vertical axis, or degrees_per_frame) is rendered with each sampler at each budget (samples per
// pixel for MIS, particles per pixel for the others, with 4 N candidates), and every frame
// is compared with a converged reference (MIS at reference_spp, pixel centres, another seed):
//   rmse            root mean square over the ball's pixels and RGB of the difference, divided
//                   by the RMS of the reference (relative), per frame
//   seconds         wall time of the frame on all worker threads
// The reference's own error (two seeds' RMSE / sqrt 2) is reported; it is far below the errors
// compared at the default settings.
//
// Equal time: for each material and each SIR budget, the RMSE of MIS, SMC and SMC bridges at
// SIR's mean frame time, interpolated on the log-log curve of RMSE against time of their budgets (not
// extrapolated: outside their measured times the entry is null).
//
// Results: DIR/relight-bench.json (rows, summary, equal_time), DIR/relight-bench.csv (one row per
// material x sampler x budget x frame), DIR/rmse-vs-time.png (log-log, one panel per material),
// DIR/frames-<material>.png (reference | MIS | SIR | SMC | SMC bridges at the middle frame, the largest budget
// whose time is within each sampler's range, side by side).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "basis/progress.h"

namespace zbrdf {

struct RelightBenchOptions {
  // Material inputs (tools/brdf_input.h); the built-in names "glossy-dbrdf" (a D-BRDF whose p(h)
  // is a GGX lobe of alpha 0.1, F0 0.9, c 0.25, 0.2, 0.15, like the wrapping paper of the
  // thesis's figure 3.11) and "diffuse" (lambert:0.5) are the defaults.
  std::vector<std::string> materials = {"glossy-dbrdf", "diffuse"};
  std::string environment = "studio";  // "studio", "sky" or an .exr / .hdr file
  int size = 64;
  int frames = 30;
  double degrees_per_frame = 0;  // the turn between frames; 0: one whole turn, 360 / frames
  std::vector<int> budgets = {2, 4, 8, 16};
  int reference_spp = 2048;
  double history_weight = 1;  // SMC
  int bridges = 2;             // SMC bridges
  double ess_threshold = 0.5;  // SMC bridges
  uint64_t seed = 1;
  std::string out_dir;
  ProgressCallback progress;

  // Throws InvalidOptions naming every field out of range.
  void Validate() const;
};

// Runs the benchmark and writes its files; returns relight-bench.json's content.
nlohmann::json RunRelightBench(const RelightBenchOptions& options);

// log-log interpolation of y at x on the curve (xs increasing after sorting by x); NaN outside.
double InterpolateLogLog(std::vector<std::pair<double, double>> curve, double x);

}  // namespace zbrdf
