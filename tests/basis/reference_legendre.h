// Test-only reference for normalized associated Legendre functions, independent of basis/:
// the unnormalized recurrence
//   P_m^m = (-1)^m (2m-1)!! s^m,  P_{m+1}^m = (2m+1) x P_m^m,
//   (l-m) P_l^m = (2l-1) x P_l-1^m - (l+m-1) P_l-2^m,
// in long double, normalized afterwards by K_l^m = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!) from
// lgammal. Different recurrence, precision and normalization path than the library.
#pragma once

#include <cmath>

namespace zbrdf::testing {

inline long double ReferencePbar(int l, int m, long double x, long double s) {
  long double pmm = 1.0L;
  for (int k = 1; k <= m; ++k) pmm *= -(2.0L * k - 1.0L) * s;
  long double value = pmm;
  if (l > m) {
    long double p_prev = pmm, p = (2.0L * m + 1.0L) * x * pmm;
    for (int k = m + 2; k <= l; ++k) {
      const long double next = ((2.0L * k - 1.0L) * x * p - (k + m - 1.0L) * p_prev) / (k - m);
      p_prev = p;
      p = next;
    }
    value = p;
  }
  const long double log_ratio = std::lgamma(static_cast<long double>(l - m + 1)) -
                                std::lgamma(static_cast<long double>(l + m + 1));
  const long double k_lm =
      std::sqrt((2.0L * l + 1.0L) / (4.0L * 3.14159265358979323846264338327950288L) *
                std::exp(log_ratio));
  return k_lm * value;
}

inline long double ReferencePbar(int l, int m, long double x) {
  return ReferencePbar(l, m, x, std::sqrt((1.0L - x) * (1.0L + x)));
}

}  // namespace zbrdf::testing
