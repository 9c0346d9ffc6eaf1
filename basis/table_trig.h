// Trigonometry for the simulator's per-sample inner loops (docs/simulator.md, "Where the time
// goes"): a table of exact values at regular nodes and a short Taylor series for the remainder,
// within 4e-16 (sin, cos) and 6e-16 (atan2) of the true values (tests/basis/table_trig_test.cc,
// against long double) and several times faster than the C library's general functions, whose
// range reduction and branches on the argument's size these callers do not need.
#pragma once

#include <array>
#include <cmath>

#include "basis/vec3.h"

namespace zbrdf {

namespace table_trig_internal {
inline constexpr int kSinCosNodes = 4096;  // per turn
inline constexpr int kAtanNodes = 256;     // over [0, 1]
// cos and sin of 2 pi k / kSinCosNodes for k <= kSinCosNodes, interleaved so that a lookup
// reads one cache line, and atan(k / kAtanNodes) for k <= kAtanNodes; computed in long double
// and rounded once to double (68 kB in all).
struct Tables {
  Tables();
  std::array<double, 2 * (kSinCosNodes + 1)> cos_sin;
  std::array<double, kAtanNodes + 1> atan;
};
inline const Tables& GetTables() {
  static const Tables tables;
  return tables;
}
}  // namespace table_trig_internal

// *c = cos(2 pi u), *s = sin(2 pi u) for u in [0, 1] (an azimuth in turns); outside it, the C
// library's sin and cos.
inline void TurnSinCos(double u, double* s, double* c) {
  using namespace table_trig_internal;
  if (!(u >= 0.0 && u <= 1.0)) {
    *s = std::sin(2 * M_PI * u);
    *c = std::cos(2 * M_PI * u);
    return;
  }
  const double scaled = u * kSinCosNodes;
  const int k = static_cast<int>(scaled);  // <= kSinCosNodes
  // The remainder in radians, below 2 pi / 4096 = 1.5e-3: the series' next terms, d^7 / 5040
  // and d^6 / 720, are below 2e-23 and 2e-20.
  const double d = (scaled - k) * (2 * M_PI / kSinCosNodes);
  const double d2 = d * d;
  const double sin_d = d * (1.0 - d2 * (1.0 / 6.0) * (1.0 - d2 * (1.0 / 20.0)));
  const double cos_d_minus_1 = -0.5 * d2 * (1.0 - d2 * (1.0 / 12.0));
  const double* t = &GetTables().cos_sin[2 * static_cast<size_t>(k)];
  // cos(a + d) = cos a + (cos a (cos d - 1) - sin a sin d), sin likewise: the small
  // corrections added last keep the table's rounding.
  *c = t[0] + (t[0] * cos_d_minus_1 - t[1] * sin_d);
  *s = t[1] + (t[1] * cos_d_minus_1 + t[0] * sin_d);
}

// atan2(y, x) in [-pi, pi] for finite x, y not both 0; otherwise the C library's atan2.
inline double TableAtan2(double y, double x) {
  using namespace table_trig_internal;
  const double ax = std::fabs(x), ay = std::fabs(y);
  const bool swap = ay > ax;
  const double num = swap ? ax : ay, den = swap ? ay : ax;
  const double t = num / den;  // in [0, 1] unless x, y are 0, infinite or NaN:
  if (!(den > 0.0 && den < INFINITY && t <= 1.0)) return std::atan2(y, x);
  const int k = static_cast<int>(t * kAtanNodes + 0.5);  // nearest node t_k = k / 256
  const double t_k = static_cast<double>(k) / kAtanNodes;
  // atan t = atan t_k + atan r with r = (t - t_k) / (1 + t t_k), |r| <= 1 / 512: the series'
  // next term, r^7 / 7, is below 2e-20.
  const double r = (t - t_k) / (1.0 + t * t_k);
  const double r2 = r * r;
  const double atan_r = r * (1.0 - r2 * (1.0 / 3.0 - r2 * (1.0 / 5.0)));
  double a = GetTables().atan[k] + atan_r;
  if (swap) a = M_PI / 2 - a;
  if (x < 0) a = M_PI - a;
  return y < 0 || (y == 0 && std::signbit(y)) ? -a : a;
}

// SphericalPhi of a direction (basis/vec3.h) by TableAtan2: its azimuth in [0, 2 pi). (Its
// polar angle is left to acos: a table's atan2 of sqrt(x^2 + y^2) and z measured no faster.)
inline double TableSphericalPhi(const Vec3& w) {
  const double p = TableAtan2(w.y, w.x);
  return p < 0 ? p + 2 * M_PI : p;
}

// acos(z) within 1.3e-11 (tests/basis/table_trig_test.cc, against long double), for callers
// that need a polar angle to far less than double precision and call it per sample: the
// transport build's grid lookups (a cell's fraction to 1e-8 of a 0.1 deg cell). About a sixth
// of the C library's acos: a square root and eleven multiply-adds, no branch on the argument
// but its sign. The form of Abramowitz & Stegun 4.4.45, acos(x) = sqrt(1 - x) p(x) on [0, 1],
// with p the degree-11 Chebyshev fit of acos(x) / sqrt(1 - x) there (smooth: sqrt(2) (1 +
// (1 - x) / 12 + ...) at x = 1); acos(-x) = pi - acos(x). z outside [-1, 1] is clamped, as
// SphericalTheta does; NaN stays NaN.
inline double ApproxAcos(double z) {
  const double x = std::fabs(z) < 1.0 ? std::fabs(z) : (std::isnan(z) ? z : 1.0);
  double p = -0.00014193063147947618;
  p = p * x + 0.0010184474839831212;
  p = p * x - 0.0034473872770873332;
  p = p * x + 0.0075337808256499984;
  p = p * x - 0.012492026216814448;
  p = p * x + 0.017799378526530504;
  p = p * x - 0.024156062902908317;
  p = p * x + 0.033645766930125311;
  p = p * x - 0.05078934325174729;
  p = p * x + 0.089048445114015634;
  p = p * x - 0.21460183301887759;
  p = p * x + 1.5707963267828322;
  const double a = std::sqrt(1.0 - x) * p;
  return z < 0 ? M_PI - a : a;
}

}  // namespace zbrdf
