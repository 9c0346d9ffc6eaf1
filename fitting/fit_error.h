// How far a fitted or converted BRDF is from the truth, over pairs of directions.
//
// All errors compare f^ = f_r cos(theta_i), the measured quantity, and are relative L2 norms
// over pairs (w_i, w_o) of upper-hemisphere directions (solid-angle measure in both):
//   cosine_l2     over the whole hemisphere: the cosine-weighted L2 of Ngan, Durand & Matusik
//                 2005 ("Experimental Analysis of BRDF Models", section 5: sqrt of the integral
//                 of ((f_model - f_true) cos theta_i)^2), divided by the same norm of the truth,
//                 over the full hemisphere (no 80 deg cut-off);
//   in_zone       over pairs with both directions in the measured zone;
//   outside_zone  over the other pairs (at least one direction outside the zone).
// cosine_l2_80 restricts the norms to pairs with both directions within 80 deg of the normal, the
// domain Ngan et al. used. All three channels enter the norms. negative_fraction is the share of the hemisphere pairs
// (by measure) where some channel of the model's f^ is negative (ringing of band-limited
// reconstructions; 0 for any BRDF that clamps).
//
// Quadrature. w_o: Gauss-Legendre in cos(theta) on the pieces [0, cos theta_max], [cos theta_max,
// cos theta_min], [cos theta_min, 1] (the zone boundary is exact) with nodes in proportion to
// their length, at four azimuths 90 deg apart (exact for isotropic BRDFs; for anisotropic ones
// exact up to the third azimuthal harmonic). w_i: through the half vector h, w_i = 2 (w_o.h) h -
// w_o, dw_i = 4 (w_o.h) dw_h (Walter et al. 2007, eq. 14), with Gauss-Legendre in theta_h on
// pieces [0, 0.25, 1, 3, 8, 20, 45, 90] deg and the trapezoid rule in phi_h: measured materials
// such as MERL's blue-acrylic have specular peaks well under 1 deg wide, which a grid in w_i
// misses or overweights; in h they sit at theta_h = 0, where the rule is finest. Pairs with w_i
// below the horizon contribute 0 (f^ vanishes there). The zone split of w_i is by node, so its
// boundary is resolved to the node spacing (about 1-4 deg); the hemisphere norm has no boundary.
#pragma once

#include <functional>
#include <span>

#include "basis/zone.h"
#include "brdf/brdf.h"

namespace zbrdf {

// f^(w_i[k], w_o) for one exitant direction and many incident ones.
using CosineWeightedFn =
    std::function<void(const Vec3& w_o, std::span<const Vec3> w_i, std::span<Rgb> f_hat)>;
// f_r(w_i, w_o) cos(theta_i) from a Brdf's EvalBatch.
CosineWeightedFn CosineWeightedOf(const Brdf& brdf);

struct BrdfComparisonOptions {
  int half_theta_per_piece = 8, half_phi = 96;  // h rule: Gauss nodes per theta_h piece, phi_h
  int exitant_theta = 24, exitant_phi = 4;      // w_o rule

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct BrdfComparison {
  double cosine_l2 = 0;
  double cosine_l2_80 = 0;       // the same over pairs with both directions within 80 deg of the
                                 // normal (Ngan et al.'s domain: MERL is unreliable beyond it)
  double in_zone = 0;
  double outside_zone = 0;       // 0 when the zone is the whole hemisphere (has_outside false)
  bool has_outside = true;
  double negative_fraction = 0;
  // The same norms taken per channel and averaged over R, G, B: Ngan et al.'s definition,
  // which weighs a dim channel as much as a bright one (data/baselines/README.md).
  double cosine_l2_channel_mean = 0, cosine_l2_80_channel_mean = 0, in_zone_channel_mean = 0;
};

BrdfComparison CompareBrdfs(const CosineWeightedFn& model, const CosineWeightedFn& truth,
                            const Zone& zone, const BrdfComparisonOptions& options = {});
inline BrdfComparison CompareBrdfs(const Brdf& model, const Brdf& truth, const Zone& zone,
                                   const BrdfComparisonOptions& options = {}) {
  return CompareBrdfs(CosineWeightedOf(model), CosineWeightedOf(truth), zone, options);
}

}  // namespace zbrdf
