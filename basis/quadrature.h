// Quadrature rules on [-1, 1], on a zone's cos(theta) range, and over a zone of the sphere.
//
// Exactness (docs/design.md section 3): the product rule of n_theta Gauss-Legendre nodes in
// cos(theta) and n_phi trapezoid points in phi integrates exactly any product of two SH (or two
// ZB) functions of order <= L when n_theta >= L + 1 and n_phi >= 2L + 1. Mixed products Y x Z
// with odd m are not polynomial in cos(theta); for those use Gauss-Legendre in psi, where
// t = cos(psi) is the zone's virtual-sphere coordinate: the integrand is then smooth in psi and
// the rule converges exponentially.
#pragma once

#include <vector>

#include "basis/vec3.h"
#include "basis/zone.h"

namespace zbrdf {

// Gauss-Legendre nodes (ascending) and weights on [-1, 1]; exact for polynomials of degree
// <= 2n - 1. Newton iteration on P_n; nodes accurate to a few ulps for n <= 2000.
struct GaussLegendreRule {
  std::vector<double> nodes;
  std::vector<double> weights;
};
GaussLegendreRule GaussLegendre(int n);

// A rule for integral_a^b g(x) dx over a zone's x = cos(theta) in [a, b]. Each node also
// carries the zone's virtual coordinate t and s = sqrt(1 - t^2) (exact for the psi rule), and
// sqrt(1 - x^2), so that callers need not recompute them with cancellation.
struct CosThetaRule {
  std::vector<double> x, weight, t, s_t, s_x;
};
// Gauss-Legendre in x mapped to [a, b].
CosThetaRule CosThetaGaussRule(const Zone& zone, int n);
// Gauss-Legendre in psi in [0, pi] with t = cos(psi), x = (a+b)/2 + (b-a)/2 t,
// dx = (b-a)/2 sin(psi) dpsi.
CosThetaRule CosThetaPsiRule(const Zone& zone, int n);

// A rule over the zone's directions: integral_Z g(w) dw ~= sum_k weight[k] g(direction[k]).
struct SphereRule {
  std::vector<Vec3> directions;
  std::vector<double> weights;
};
// theta_rule x trapezoid with n_phi points in phi (phi_j = 2 pi j / n_phi).
SphereRule ProductRule(const CosThetaRule& theta_rule, int n_phi);

}  // namespace zbrdf
