#include "basis/legendre.h"

#include <cmath>

#include "basis/error.h"

namespace zbrdf {

namespace {

// Sectoral value Pbar_m^m(x) = (-1)^m sqrt((2m+1)!! / (4 pi (2m)!!)) s^m, by the stable product
// Pbar_m^m = -sqrt((2m+1)/(2m)) s Pbar_{m-1}^{m-1}.
double Sectoral(int m, double s) {
  double p = 0.5 / std::sqrt(M_PI);  // Pbar_0^0 = 1 / sqrt(4 pi)
  for (int k = 1; k <= m; ++k) p *= -std::sqrt((2.0 * k + 1.0) / (2.0 * k)) * s;
  return p;
}

}  // namespace

void NormalizedLegendreOrder(int max_degree, int m, double x, double s, double* out) {
  ZBRDF_ASSERT(max_degree >= 0 && max_degree <= kMaxLegendreDegree,
               "Legendre degree out of range");
  ZBRDF_ASSERT(m >= 0 && m <= max_degree, "Legendre order out of range");
  double p_prev = Sectoral(m, s);  // Pbar_m^m
  out[0] = p_prev;
  if (m == max_degree) return;
  double p = std::sqrt(2.0 * m + 3.0) * x * p_prev;  // Pbar_{m+1}^m
  out[1] = p;
  for (int l = m + 2; l <= max_degree; ++l) {
    const double l2 = static_cast<double>(l) * l;
    const double m2 = static_cast<double>(m) * m;
    const double a = std::sqrt((4.0 * l2 - 1.0) / (l2 - m2));
    const double b = std::sqrt(((l - 1.0) * (l - 1.0) - m2) / (4.0 * (l - 1.0) * (l - 1.0) - 1.0));
    const double p_next = a * (x * p - b * p_prev);
    out[l - m] = p_next;
    p_prev = p;
    p = p_next;
  }
}

void NormalizedLegendreAll(int max_degree, double x, double s, double* out) {
  ZBRDF_ASSERT(max_degree >= 0 && max_degree <= kMaxLegendreDegree,
               "Legendre degree out of range");
  double p_mm = 0.5 / std::sqrt(M_PI);
  for (int m = 0; m <= max_degree; ++m) {
    if (m > 0) p_mm *= -std::sqrt((2.0 * m + 1.0) / (2.0 * m)) * s;
    double p_prev = p_mm;
    out[LegendreIndex(m, m)] = p_prev;
    if (m == max_degree) break;
    double p = std::sqrt(2.0 * m + 3.0) * x * p_prev;
    out[LegendreIndex(m + 1, m)] = p;
    const double m2 = static_cast<double>(m) * m;
    for (int l = m + 2; l <= max_degree; ++l) {
      const double l2 = static_cast<double>(l) * l;
      const double a = std::sqrt((4.0 * l2 - 1.0) / (l2 - m2));
      const double b =
          std::sqrt(((l - 1.0) * (l - 1.0) - m2) / (4.0 * (l - 1.0) * (l - 1.0) - 1.0));
      const double p_next = a * (x * p - b * p_prev);
      out[LegendreIndex(l, m)] = p_next;
      p_prev = p;
      p = p_next;
    }
  }
}

}  // namespace zbrdf
