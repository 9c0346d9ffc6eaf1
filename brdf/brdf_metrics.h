// Error metrics between two BRDFs (`zbrdf compare`, `zbrdf report`).
//
// Cosine-weighted L2 (Ngan, Durand & Matusik 2005, "Experimental Analysis of BRDF Models",
// section 4: the fitting error weights f_r by cos(theta_i), which de-emphasizes grazing
// incidence, where measurements are least reliable and contribute least to images), per RGB
// channel, as a root mean square over the pairs of the upper hemisphere:
//   E = sqrt( 1 / (2 pi)^2  integral_H integral_H (f_a - f_b)^2 cos^2(theta_i) dw_i dw_o ).
// Relative: E divided by the same norm of f_a. Estimated by Monte Carlo with w_o uniform on the
// hemisphere and w_i from the defensive mixture, in equal parts, of both BRDFs' samplers (not
// a delta material's) and the uniform hemisphere, fixed seed; the standard error is reported
// with the estimate.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>

#include "brdf/brdf.h"

namespace zbrdf {

struct BrdfDistance {
  Rgb l2;                 // E per channel, 1/sr
  Rgb l2_standard_error;  // one standard error of E (delta method)
  Rgb reference_norm;     // the same norm of f_a
  double Mean() const { return l2.Average(); }
  double RelativeMean() const;  // mean over channels of E / norm(f_a), 0/0 -> 0
  nlohmann::json ToJson() const;
};

BrdfDistance CosineWeightedL2(const Brdf& a, const Brdf& b, int64_t samples = 1 << 18,
                              uint64_t seed = 1);

}  // namespace zbrdf
