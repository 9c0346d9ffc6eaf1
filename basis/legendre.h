// Normalized associated Legendre functions, the building block of SH and of the zonal basis.
//
// We compute Pbar_l^m(x) = K_l^m P_l^m(x) for 0 <= m <= l <= L, where
//   K_l^m = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!)
// and P_l^m includes the Condon-Shortley phase (-1)^m. With this normalization
//   integral_{-1}^{1} Pbar_l^m(x) Pbar_l'^m(x) dx = delta_ll' / (2 pi),
// so real SH are Y_l0 = Pbar_l^0 and Y_l,+-m = sqrt(2) Pbar_l^m(cos theta) {cos, sin}(m phi).
//
// Method: sectoral seed Pbar_m^m from Pbar_{m-1}^{m-1}, then the three-term recurrence in l
// (e.g. Holmes & Featherstone 2002). The factorial ratio is never formed. The caller passes
// s = sqrt(1 - x^2) separately, so that the zonal basis can form it without cancellation near
// the zone edges (docs/design.md section 3). Accuracy: the values are correctly rounded doubles
// of the extended-precision recurrence, absolute error <= 1e-14 for l <= 60 (5e-15 measured, from
// the rounding of s^m).
#pragma once

#include <cmath>

namespace zbrdf {

inline constexpr int kMaxLegendreDegree = 60;

// Index of (l, m), 0 <= m <= l, in the triangular output array.
constexpr int LegendreIndex(int l, int m) { return l * (l + 1) / 2 + m; }
// Number of (l, m) pairs with l <= max_degree.
constexpr int LegendreCount(int max_degree) { return (max_degree + 1) * (max_degree + 2) / 2; }

// Fills out[LegendreIndex(l, m)] = Pbar_l^m(x) for all 0 <= m <= l <= max_degree.
// Requires x in [-1, 1], s = sqrt(1 - x^2) >= 0, 0 <= max_degree <= kMaxLegendreDegree.
// out must hold LegendreCount(max_degree) values.
void NormalizedLegendreAll(int max_degree, double x, double s, double* out);

// Same values for a single order m: out[l - m] = Pbar_l^m(x) for l = m..max_degree.
// out must hold max_degree - m + 1 values.
void NormalizedLegendreOrder(int max_degree, int m, double x, double s, double* out);

// The same with x and s in extended precision, for callers that form x near the poles as
// 1 - (1 - x) (the zonal basis at its zone edges): rounding x to double there would cost
// |dPbar/dx| * ulp(1) ~ l^2 * 1e-16 of accuracy.
void NormalizedLegendreAll(int max_degree, long double x, long double s, double* out);
void NormalizedLegendreOrder(int max_degree, int m, long double x, long double s, double* out);

// cos(m delta) for m = 0..order, by the Chebyshev recurrence cos(m d) = 2 cos(d) cos((m-1) d) -
// cos((m-2) d): the azimuthal factors that multiply the associated Legendre functions.
// CosMultiplesOfCos takes cos(delta) itself, for callers that keep it.
inline void CosMultiplesOfCos(int order, double cos_delta, double* out) {
  out[0] = 1.0;
  if (order >= 1) out[1] = cos_delta;
  for (int m = 2; m <= order; ++m) out[m] = 2.0 * cos_delta * out[m - 1] - out[m - 2];
}
inline void CosMultiples(int order, double delta, double* out) {
  CosMultiplesOfCos(order, std::cos(delta), out);
}

}  // namespace zbrdf
