// The conditioning report users pick their capture order and conversion target from
// (`zbrdf basis`).
//
// For a zone, a ZB order L and a target basis of order L2 it reports how exactly the ZB is
// integrated, how ill-conditioned the target's Gram matrix on the zone is (per |m|), the Shannon
// number (how many target functions the zone can determine, docs/design.md section 3 item 1), the
// conversion's noise gain and truncated components at tau, and a round trip of a random
// band-limited function (fixed seed): its ZB moments by quadrature, converted back, compared
// with the function inside the zone and over the rest of the upper hemisphere.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "basis/target_basis.h"
#include "basis/zone.h"

namespace zbrdf {

struct ConditioningOptions {
  double theta_min_rad = 0, theta_max_rad = 0;
  int zb_order = 4;
  int target_order = 4;
  TargetKind target = TargetKind::kSh;
  double tau = 1e-13;
  // White noise added to the moments in the noisy round trip, relative to their RMS; 1e-3 is
  // a typical HDR capture's coefficient noise.
  double noise_relative = 1e-3;
  uint64_t seed = 1;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct ConditioningReport {
  ConditioningOptions options;
  int zb_size = 0, target_size = 0;
  double zb_orthonormality_max_error = 0;   // max |integral Z_a Z_b - delta| by (L+1)x(2L+1) rule
  std::vector<double> gram_condition_per_m;  // cond of the target Gram block, |m| = 0..L2
  // True where the condition exceeds what double precision resolves (reported as 1/eps).
  std::vector<bool> gram_condition_saturated;
  double shannon_number = 0;                 // trace of the target Gram matrix on the zone
  double noise_gain = 0;                     // ||C||_2
  int truncated_components = 0;
  int underdetermined_components = 0;
  double largest_singular_value = 0, smallest_kept_singular_value = 0;
  double roundtrip_error_in_zone = 0;        // relative L2 over the zone
  double roundtrip_error_outside_zone = 0;   // relative L2 over the upper hemisphere outside it
  // The same with noise_relative white noise on the moments: what a measurement can expect.
  double noisy_roundtrip_error_in_zone = 0;
  double noisy_roundtrip_error_outside_zone = 0;
  bool has_outside = true;                   // false when the zone is the whole hemisphere
  std::vector<std::string> warnings;
};

ConditioningReport AnalyzeConditioning(const ConditioningOptions& options);

// How far an estimate f_est = sum_i y_est_i T_i is from f = sum_i y_i T_i over the band of
// directions theta in [lo, hi] (all azimuths), T the target functions: the round-trip errors
// above, and the tests of conversions.
struct BandError {
  double error_sq = 0;  // integral (f_est - f)^2 dw over the band (0 where f vanishes on it)
  double norm_sq = 0;   // integral f^2 dw over the band
  // sqrt(error_sq / norm_sq), the relative L2 error; 0 when f vanishes on the band.
  double Relative() const;
};
// By the product rule of 2 order + 12 Gauss-Legendre nodes in cos theta and 2 order + 3
// trapezoid points in phi, exact for products of two target functions (docs/design.md section 3,
// quadrature). An empty band (hi - lo < 1e-12 rad) gives zeros; bands must lie in [0, 90] deg.
BandError ErrorOverBand(const TargetBasis& target, const Eigen::VectorXd& y,
                        const Eigen::VectorXd& y_est, double lo_rad, double hi_rad);

}  // namespace zbrdf
