// Zonal data to spherical harmonics (`zbrdf convert --to sh`): the tensor-product conversion by
// the moment form (basis/conversion.h, docs/design.md section 3 item 3), regularized from the
// data's own variances, with per-exitant tables for renderers (brdf/sh_file.h).
//
// Automatic truncation (tau not given). With the moment matrix M = U Sigma V^T (the ZB moments
// of the target functions, the same on both sides of the tensor), the data seen along singular
// direction a are row a and column a of W = U^T Z U (all channels): energy e_a, and noise n_a =
// the sum of Var(W_ab) = sum_kj U_ka^2 Var(Z_kj) U_jb^2 (independent coefficient noise) over
// them. Converting divides by s_a, so keeping the k largest directions costs
//   E(k) = sum_{a <= k} n_a / s_a^2  +  sum_{a > k} [e_a >= 8 n_a] (e_a - n_a) / s_a^2,
// amplified noise plus truncated signal, where signal counts only where it is significant (8
// times the noise energy); k minimizes E, and tau lies between s_k and s_k+1 (relative to s_1).
// So a direction is truncated when its amplified noise outweighs the signal it carries; and never
// is tau below 1e-4 (noise gain 1e4: the tensor is stored in float and captured with ~1e-3
// relative errors, so nothing beyond that gain is trustworthy whatever the estimate says). The
// noise is the recorded variances' (floored at (1e-7 |z|)^2 for float storage) or, if larger,
// the median energy of the directions the zone barely sees (s_a <= 1e-3 s_1): a band-limited
// function of bounded norm leaves at most 1e-3 of its amplitude there, so what the data show
// along them is error -- photon noise, the capture's systematic errors, and the out-of-band
// content of features sharper than the order (a specular peak's moments spread evenly over all
// directions).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "basis/conversion.h"
#include "basis/target_basis.h"
#include "brdf/sh_file.h"
#include "fitting/fit_data.h"

namespace zbrdf {

struct ShConversionOptions {
  TargetKind target = TargetKind::kSh;
  int order = -1;       // target order; < 0: the data's order
  double tau = -1;      // < 0: automatic (above)
  int exitant_theta = 90, exitant_phi = 90;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct ShConversionResult {
  ShBrdfData data;
  ConversionDiagnostics diagnostics;  // noise gain, truncated components, singular values
  double tau = 0;
  bool tau_automatic = false;
  int kept_directions = 0;            // singular directions kept (per side)
  int singular_directions = 0;        // available (per side)
  double shannon_number = 0;          // (L+1)^2 (b - a) / 2 for the target order
  std::vector<std::string> warnings;  // extrapolation, truncation, basis choice

  nlohmann::json ToJson() const;
};

// Throws InputError for a bad order or tau; NumericalError if the data hold non-finite values.
ShConversionResult ConvertToSh(const ZonalTensor& data, const ShConversionOptions& options);

}  // namespace zbrdf
