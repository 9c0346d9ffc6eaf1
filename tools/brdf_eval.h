// `zbrdf eval`: f_r at direction pairs given as text, for scripts and cross-checks with other
// tools (docs/eval.md).
//
// Input, one pair per line: theta_i phi_i theta_o phi_o in radians in the sample frame (normal
// +z, phi from +x; w_i toward the light, w_o toward the viewer), separated by spaces, tabs or a
// comma; '#' starts a comment; blank lines are skipped. Output per pair: the four angles and
// f_r R G B in 1/sr (no cosine), every number as printf's %.17g (round-trips a double). A pair
// with either direction below the horizon (cos theta <= 0) gives 0.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "brdf/brdf.h"

namespace zbrdf {

struct DirectionPair {
  double theta_i = 0, phi_i = 0, theta_o = 0, phi_o = 0;
};

// Parses the whole text (in parallel). Throws InputError "SOURCE line N: ..." for the first
// malformed line: not four fields, a field that is not a number, or a non-finite number.
std::vector<DirectionPair> ParseDirectionPairs(std::string_view text, const std::string& source);

// f_r for every pair (in parallel, through Brdf::EvalBatch); 0 below the horizon.
std::vector<Rgb> EvaluatePairs(const Brdf& brdf, std::span<const DirectionPair> pairs);

// The same for pairs of unit vectors: f[k] = f_r(w_i[k], w_o[k]), through Brdf::EvalBatch in
// blocks of 4096 pairs on all cores; 0 where either direction is below the horizon. The three
// spans have one size. EvaluatePairs and the Python module's eval both come here.
void EvaluateDirections(const Brdf& brdf, std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                        std::span<Rgb> f);

enum class EvalFormat { kCsv, kJson };

// CSV: a header line "theta_i,phi_i,theta_o,phi_o,r,g,b" and one line per pair. JSON: an object
// with "input", "brdf", "units", "columns" and "rows" (arrays of seven numbers; a non-finite
// f_r is null). `input` and `spec` only go into the JSON header.
std::string FormatEvaluations(std::span<const DirectionPair> pairs, std::span<const Rgb> f,
                              EvalFormat format, const std::string& input, const std::string& spec);

}  // namespace zbrdf
