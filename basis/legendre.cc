#include "basis/legendre.h"

#include <cmath>

#include "basis/error.h"

namespace zbrdf {

namespace {

// The recurrence runs in long double (x87 extended precision on x86-64). In double, rounding
// errors accumulate along the recurrence like l * eps * log(l) near the poles (|x| -> 1, the
// zone edges in the ZB), reaching 4e-14 at l = 30 and 1.5e-13 at l = 60; in extended precision
// the result is correctly rounded to double for all l <= 60 (legendre_test.cc). Coefficients are
// tabulated once, which also makes the evaluation 6x faster than recomputing the square roots.
using Real = long double;

struct RecurrenceTable {
  Real sectoral[kMaxLegendreDegree + 1];       // -sqrt((2m+1)/(2m)), m >= 1
  Real first[kMaxLegendreDegree + 1];          // sqrt(2m+3)
  Real a[kMaxLegendreDegree + 1][kMaxLegendreDegree + 1];  // [l][m]
  Real b[kMaxLegendreDegree + 1][kMaxLegendreDegree + 1];

  RecurrenceTable() {
    for (int m = 0; m <= kMaxLegendreDegree; ++m) {
      sectoral[m] = m == 0 ? 1.0L : -std::sqrt((2.0L * m + 1.0L) / (2.0L * m));
      first[m] = std::sqrt(2.0L * m + 3.0L);
      for (int l = m + 2; l <= kMaxLegendreDegree; ++l) {
        const Real l2 = static_cast<Real>(l) * l, m2 = static_cast<Real>(m) * m;
        a[l][m] = std::sqrt((4.0L * l2 - 1.0L) / (l2 - m2));
        b[l][m] = std::sqrt(((l - 1.0L) * (l - 1.0L) - m2) / (4.0L * (l - 1.0L) * (l - 1.0L) - 1.0L));
      }
    }
  }
};

const RecurrenceTable& Table() {
  static const RecurrenceTable table;
  return table;
}

// 1 / sqrt(4 pi) = Pbar_0^0.
constexpr Real kPbar00 = 0.282094791773878143474039725780386292922L;

// Pbar_l^m for l = m..max_degree into out[l - m], given Pbar_m^m.
inline void RecurInDegree(const RecurrenceTable& t, int max_degree, int m, Real x, Real p_mm,
                          double* out) {
  Real p_prev = p_mm;
  out[0] = static_cast<double>(p_prev);
  if (m == max_degree) return;
  Real p = t.first[m] * x * p_prev;
  out[1] = static_cast<double>(p);
  for (int l = m + 2; l <= max_degree; ++l) {
    const Real next = t.a[l][m] * (x * p - t.b[l][m] * p_prev);
    out[l - m] = static_cast<double>(next);
    p_prev = p;
    p = next;
  }
}

}  // namespace

void NormalizedLegendreOrder(int max_degree, int m, double x, double s, double* out) {
  NormalizedLegendreOrder(max_degree, m, static_cast<Real>(x), static_cast<Real>(s), out);
}

void NormalizedLegendreAll(int max_degree, double x, double s, double* out) {
  NormalizedLegendreAll(max_degree, static_cast<Real>(x), static_cast<Real>(s), out);
}

void NormalizedLegendreOrder(int max_degree, int m, long double x, long double s, double* out) {
  ZBRDF_ASSERT(max_degree >= 0 && max_degree <= kMaxLegendreDegree,
               "Legendre degree out of range");
  ZBRDF_ASSERT(m >= 0 && m <= max_degree, "Legendre order out of range");
  const RecurrenceTable& t = Table();
  Real p_mm = kPbar00;
  for (int k = 1; k <= m; ++k) p_mm *= t.sectoral[k] * s;
  RecurInDegree(t, max_degree, m, x, p_mm, out);
}

void NormalizedLegendreAll(int max_degree, long double xl, long double sl, double* out) {
  ZBRDF_ASSERT(max_degree >= 0 && max_degree <= kMaxLegendreDegree,
               "Legendre degree out of range");
  const RecurrenceTable& t = Table();
  Real p_mm = kPbar00;
  for (int m = 0; m <= max_degree; ++m) {
    if (m > 0) p_mm *= t.sectoral[m] * sl;
    Real p_prev = p_mm;
    out[LegendreIndex(m, m)] = static_cast<double>(p_prev);
    if (m == max_degree) break;
    Real p = t.first[m] * xl * p_prev;
    out[LegendreIndex(m + 1, m)] = static_cast<double>(p);
    for (int l = m + 2; l <= max_degree; ++l) {
      const Real next = t.a[l][m] * (xl * p - t.b[l][m] * p_prev);
      out[LegendreIndex(l, m)] = static_cast<double>(next);
      p_prev = p;
      p = next;
    }
  }
}

}  // namespace zbrdf
