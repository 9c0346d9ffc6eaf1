// The orthonormal zonal basis (ZB) of a spherical zone (Ghosh 2007, eq. 3.9-3.11).
//
// With a = cos(theta_max), b = cos(theta_min) and the virtual-sphere coordinate
//   t = (2 cos(theta) - a - b) / (b - a)  in [-1, 1],
//   Z_lm(theta, phi) = sqrt(2 / (b - a)) Y_lm(arccos t, phi)   inside the zone, 0 outside.
// The Z_lm are exactly orthonormal over the zone (docs/design.md section 3); for the zone
// [0, 90] deg they are the hemispherical harmonics (Gautron et al. 2004).
//
// Edge accuracy: 1 - t = 2 (b - x) / (b - a) and 1 + t = 2 (x - a) / (b - a) are formed
// directly, so sqrt(1 - t^2) keeps full relative precision at the zone edges. Coefficient
// vectors use the SH ordering ShIndex(l, m).
#pragma once

#include "basis/spherical_harmonics.h"
#include "basis/vec3.h"
#include "basis/zone.h"

namespace zbrdf {

class ZonalBasis {
 public:
  // Throws InputError unless 0 <= order <= kMaxLegendreDegree.
  ZonalBasis(const Zone& zone, int order);

  const Zone& zone() const { return zone_; }
  int order() const { return order_; }
  int size() const { return ShCount(order_); }
  // sqrt(2 / (b - a)), the factor relating Z_lm to Y_lm on the virtual sphere.
  double normalization() const { return normalization_; }

  // In extended precision: near the edges t = +-(1 - small), and rounding t to double would
  // cost l^2 ulps in the functions.
  struct VirtualCoordinate {
    bool inside = false;  // cos(theta) within [a, b]
    long double t = 0;    // virtual-sphere cos, clamped to [-1, 1]
    long double s = 0;    // sqrt(1 - t^2), formed without cancellation
  };
  VirtualCoordinate MapCosTheta(double cos_theta) const;

  // out[ShIndex(l, m)] = Z_lm(w) for l <= order; all zeros outside the zone.
  void Eval(const Vec3& w, double* out) const;
  // The same from (cos theta, phi).
  void Eval(double cos_theta, double phi_rad, double* out) const;
  // The theta part: out[LegendreIndex(l, m)] = sqrt(2/(b-a)) Pbar_l^m(t), m >= 0; zeros
  // outside the zone. Z_lm = this value times 1, sqrt(2) cos(m phi) or sqrt(2) sin(|m| phi).
  void EvalThetaPart(double cos_theta, double* out) const;

 private:
  Zone zone_;
  int order_;
  double normalization_;
};

}  // namespace zbrdf
