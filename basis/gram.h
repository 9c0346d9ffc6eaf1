// Inner products of basis functions over a zone: Gram blocks and the mixed target-ZB matrix.
//
// Every function here has azimuthal factor 1, sqrt(2) cos(m phi) or sqrt(2) sin(|m| phi), so
// inner products between functions of different m (or of cos and sin type) vanish, and the
// matrices are block-diagonal by m with the +m and -m blocks equal (docs/design.md section 3, item
// 1: by |m|, not by degree l as the thesis says). Each block is
//   integral_Z f_i f_j dw = 2 pi integral_a^b f_i(x) f_j(x) dx
// with f the theta factors. Blocks are indexed by the degrees present for that |m|, ascending.
#pragma once

#include <Eigen/Dense>

#include "basis/target_basis.h"
#include "basis/zonal_basis.h"
#include "basis/zone.h"

namespace zbrdf {

// G_ij = integral_Z T_i T_j dw for the target functions with azimuthal order +-abs_m.
// Exact (Gauss-Legendre in cos theta; the integrands are polynomials in cos theta).
Eigen::MatrixXd TargetGramBlock(const TargetBasis& target, const Zone& zone, int abs_m);

// B_ij = integral_Z T_i Z_j dw, T_i the target functions of order +-abs_m, Z_j the ZB functions
// of degree abs_m + j. By Gauss-Legendre in psi (t = cos psi) with psi_nodes nodes.
Eigen::MatrixXd MixedBlock(const TargetBasis& target, const ZonalBasis& zb, int abs_m,
                           int psi_nodes);

// Nodes in psi that integrate MixedBlock to machine precision (checked against twice as many
// in the tests) for orders up to kMaxLegendreDegree.
int DefaultPsiNodes(int target_order, int zb_order);

// The full Gram matrix of the ZB, integral_Z Z_a Z_b dw in ShIndex order, by the product rule
// of n_theta Gauss-Legendre nodes in cos theta and n_phi trapezoid points in phi. It is the
// identity (to rounding) iff n_theta >= L + 1 and n_phi >= 2L + 1.
Eigen::MatrixXd ZonalGramByQuadrature(const ZonalBasis& zb, int n_theta, int n_phi);

}  // namespace zbrdf
