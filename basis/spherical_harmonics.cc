#include "basis/spherical_harmonics.h"

#include <array>
#include <cmath>

#include "basis/error.h"
#include "basis/legendre.h"

namespace zbrdf {

void ShDegreeOrder(int index, int* l, int* m) {
  ZBRDF_ASSERT(index >= 0, "negative SH index");
  int degree = static_cast<int>(std::sqrt(static_cast<double>(index)));
  while (degree * degree > index) --degree;
  while ((degree + 1) * (degree + 1) <= index) ++degree;
  *l = degree;
  *m = index - degree * degree - degree;
}

void CosSinMultiples(int max_order, double cos_phi, double sin_phi, double* cos_out,
                     double* sin_out) {
  cos_out[0] = 1.0;
  sin_out[0] = 0.0;
  for (int k = 1; k <= max_order; ++k) {
    cos_out[k] = cos_out[k - 1] * cos_phi - sin_out[k - 1] * sin_phi;
    sin_out[k] = sin_out[k - 1] * cos_phi + cos_out[k - 1] * sin_phi;
  }
}

void AssembleRealHarmonics(int order, const double* legendre, const double* cos_m,
                           const double* sin_m, double scale, double* out) {
  const double root2_scale = std::sqrt(2.0) * scale;
  for (int l = 0; l <= order; ++l) {
    const int center = l * l + l;
    out[center] = scale * legendre[LegendreIndex(l, 0)];
    for (int m = 1; m <= l; ++m) {
      const double p = root2_scale * legendre[LegendreIndex(l, m)];
      out[center + m] = p * cos_m[m];
      out[center - m] = p * sin_m[m];
    }
  }
}

void EvalShAll(int order, const Vec3& w, double* out) {
  ZBRDF_ASSERT(order >= 0 && order <= kMaxLegendreDegree, "SH order out of range");
  std::array<double, LegendreCount(kMaxLegendreDegree)> legendre;
  std::array<double, kMaxLegendreDegree + 1> cos_m, sin_m;
  const double rho = std::sqrt(w.x * w.x + w.y * w.y);
  const double cos_phi = rho > 0 ? w.x / rho : 1.0;
  const double sin_phi = rho > 0 ? w.y / rho : 0.0;
  NormalizedLegendreAll(order, std::clamp(w.z, -1.0, 1.0), std::min(rho, 1.0), legendre.data());
  CosSinMultiples(order, cos_phi, sin_phi, cos_m.data(), sin_m.data());
  AssembleRealHarmonics(order, legendre.data(), cos_m.data(), sin_m.data(), 1.0, out);
}

}  // namespace zbrdf
