// Projection of a function onto the zonal basis by direct quadrature.
#pragma once

#include <functional>

#include <Eigen/Dense>

#include "basis/vec3.h"
#include "basis/zonal_basis.h"

namespace zbrdf {

// z_j = integral_Z g(w) Z_j(w) dw for every ZB function, by Gauss-Legendre in psi (n_psi
// nodes) x trapezoid in phi (n_phi points). Exact to rounding when g is a band-limited
// function whose products with the ZB are integrated by that rule (n_phi > order + order(g),
// n_psi ~ order + order(g) + 30); for sharp g increase both.
Eigen::VectorXd ProjectOntoZonalBasis(const ZonalBasis& zb,
                                      const std::function<double(const Vec3&)>& g, int n_psi,
                                      int n_phi);

}  // namespace zbrdf
