// Real spherical harmonics Y_lm on the unit sphere.
//
// Y_l0 = Pbar_l^0(cos theta), Y_lm = sqrt(2) Pbar_l^m(cos theta) cos(m phi) for m > 0 and
// Y_lm = sqrt(2) Pbar_l^|m|(cos theta) sin(|m| phi) for m < 0, with Pbar from legendre.h
// (Condon-Shortley phase included). Orthonormal over the sphere. Coefficient vectors are
// ordered by ShIndex(l, m) = l^2 + l + m.
#pragma once

#include "basis/vec3.h"

namespace zbrdf {

constexpr int ShIndex(int l, int m) { return l * l + l + m; }
constexpr int ShCount(int order) { return (order + 1) * (order + 1); }
// Inverse of ShIndex.
void ShDegreeOrder(int index, int* l, int* m);

// out[k] = cos(k phi), sin(k phi) for k = 0..max_order, from (cos phi, sin phi) by the angle-sum
// recurrence (no trigonometric calls).
void CosSinMultiples(int max_order, double cos_phi, double sin_phi, double* cos_out,
                     double* sin_out);

// All Y_lm with l <= order at the unit vector w (any hemisphere). out holds ShCount(order).
// At the poles, where phi is undefined, every m != 0 function is 0 and phi is taken as 0.
void EvalShAll(int order, const Vec3& w, double* out);

// Combines normalized Legendre values (legendre.h layout) with azimuthal multiples into real
// SH layout. Shared by SH and the zonal basis, whose functions have the same structure.
void AssembleRealHarmonics(int order, const double* legendre, const double* cos_m,
                           const double* sin_m, double scale, double* out);

}  // namespace zbrdf
