#include "basis/zonal_basis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "basis/error.h"
#include "basis/legendre.h"

namespace zbrdf {

ZonalBasis::ZonalBasis(const Zone& zone, int order)
    : zone_(zone), order_(order),
      normalization_(std::sqrt(2.0 / (zone.cos_upper() - zone.cos_lower()))) {
  if (order < 0 || order > kMaxLegendreDegree) {
    throw InputError("zonal basis order " + std::to_string(order) + " is out of range [0, " +
                     std::to_string(kMaxLegendreDegree) + "]");
  }
}

ZonalBasis::VirtualCoordinate ZonalBasis::MapCosTheta(double cos_theta) const {
  const long double a = zone_.cos_lower(), b = zone_.cos_upper(), x = cos_theta;
  VirtualCoordinate v;
  v.inside = x >= a && x <= b;
  if (!v.inside) return v;
  const long double width = b - a;
  const long double one_minus_t = std::clamp(2.0L * (b - x) / width, 0.0L, 2.0L);
  const long double one_plus_t = std::clamp(2.0L * (x - a) / width, 0.0L, 2.0L);
  // t from whichever side is smaller keeps relative precision near that edge.
  v.t = one_minus_t < one_plus_t ? 1.0L - one_minus_t : one_plus_t - 1.0L;
  v.s = std::sqrt(one_minus_t * one_plus_t);
  return v;
}

void ZonalBasis::EvalThetaPart(double cos_theta, double* out) const {
  const VirtualCoordinate v = MapCosTheta(cos_theta);
  const int count = LegendreCount(order_);
  if (!v.inside) {
    std::fill(out, out + count, 0.0);
    return;
  }
  NormalizedLegendreAll(order_, v.t, v.s, out);
  for (int k = 0; k < count; ++k) out[k] *= normalization_;
}

void ZonalBasis::Eval(double cos_theta, double phi_rad, double* out) const {
  const VirtualCoordinate v = MapCosTheta(cos_theta);
  if (!v.inside) {
    std::fill(out, out + size(), 0.0);
    return;
  }
  std::array<double, LegendreCount(kMaxLegendreDegree)> legendre;
  std::array<double, kMaxLegendreDegree + 1> cos_m, sin_m;
  NormalizedLegendreAll(order_, v.t, v.s, legendre.data());
  CosSinMultiples(order_, std::cos(phi_rad), std::sin(phi_rad), cos_m.data(), sin_m.data());
  AssembleRealHarmonics(order_, legendre.data(), cos_m.data(), sin_m.data(), normalization_, out);
}

void ZonalBasis::Eval(const Vec3& w, double* out) const {
  const VirtualCoordinate v = MapCosTheta(w.z);
  if (!v.inside) {
    std::fill(out, out + size(), 0.0);
    return;
  }
  std::array<double, LegendreCount(kMaxLegendreDegree)> legendre;
  std::array<double, kMaxLegendreDegree + 1> cos_m, sin_m;
  const double rho = std::sqrt(w.x * w.x + w.y * w.y);
  NormalizedLegendreAll(order_, v.t, v.s, legendre.data());
  CosSinMultiples(order_, rho > 0 ? w.x / rho : 1.0, rho > 0 ? w.y / rho : 0.0, cos_m.data(),
                  sin_m.data());
  AssembleRealHarmonics(order_, legendre.data(), cos_m.data(), sin_m.data(), normalization_, out);
}

}  // namespace zbrdf
