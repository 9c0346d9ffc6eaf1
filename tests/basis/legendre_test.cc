#include "basis/legendre.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "basis/quadrature.h"
#include "tests/basis/reference_legendre.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::ReferencePbar;

double Factorial(int n) { return std::tgamma(n + 1.0); }
double K(int l, int m) {
  return std::sqrt((2 * l + 1) / (4 * M_PI) * Factorial(l - m) / Factorial(l + m));
}

TEST(Legendre, MatchesClosedFormsForSmallDegrees) {
  for (double x = -1.0; x <= 1.0; x += 1.0 / 64) {
    const double s = std::sqrt(1 - x * x);
    // Unnormalized P_l^m with the Condon-Shortley phase (Abramowitz & Stegun 8.6, 8.5.1).
    const double closed[4][4] = {
        {1, 0, 0, 0},
        {x, -s, 0, 0},
        {0.5 * (3 * x * x - 1), -3 * x * s, 3 * s * s, 0},
        {0.5 * (5 * x * x * x - 3 * x), -1.5 * (5 * x * x - 1) * s, 15 * x * s * s, -15 * s * s * s}};
    std::vector<double> p(LegendreCount(3));
    NormalizedLegendreAll(3, x, s, p.data());
    for (int l = 0; l <= 3; ++l) {
      for (int m = 0; m <= l; ++m) {
        // Values are O(1); 4 ulps of the largest term.
        EXPECT_NEAR(p[LegendreIndex(l, m)], K(l, m) * closed[l][m], 1e-15) << l << " " << m;
      }
    }
  }
}

TEST(Legendre, MatchesLongDoubleReferenceToOneEMinus14UpToDegree30) {
  constexpr int kL = 30;
  std::vector<double> p(LegendreCount(kL));
  double worst = 0;
  for (int i = 0; i <= 400; ++i) {
    // Include the poles, the equator and points clustered near the poles.
    const double x = i <= 200 ? -1.0 + i / 100.0 : std::cos(1e-6 * (i - 200));
    const double s = std::sqrt((1 - x) * (1 + x));
    NormalizedLegendreAll(kL, x, s, p.data());
    for (int l = 0; l <= kL; ++l) {
      for (int m = 0; m <= l; ++m) {
        const double ref = static_cast<double>(ReferencePbar(l, m, x));
        worst = std::max(worst, std::abs(p[LegendreIndex(l, m)] - ref));
      }
    }
  }
  EXPECT_LE(worst, 1e-14);
}

TEST(Legendre, StaysAccurateUpToDegree60) {
  constexpr int kL = kMaxLegendreDegree;
  std::vector<double> p(LegendreCount(kL));
  double worst = 0;
  for (int i = 0; i <= 300; ++i) {
    // A grid plus points within 1e-4 rad of both poles, where the recurrence is least stable.
    const double x = i <= 200 ? -1.0 + i / 100.0
                     : i <= 250 ? std::cos(2e-6 * (i - 200)) : -std::cos(2e-6 * (i - 250));
    const double s = std::sqrt((1 - x) * (1 + x));
    NormalizedLegendreAll(kL, x, s, p.data());
    for (int l = 0; l <= kL; ++l) {
      for (int m = 0; m <= l; ++m) {
        const double ref = static_cast<double>(ReferencePbar(l, m, x));
        ASSERT_TRUE(std::isfinite(p[LegendreIndex(l, m)]));
        worst = std::max(worst, std::abs(p[LegendreIndex(l, m)] - ref));
      }
    }
  }
  EXPECT_LE(worst, 1e-14);
}

TEST(Legendre, SingleOrderAgreesWithAllOrders) {
  constexpr int kL = 40;
  std::vector<double> all(LegendreCount(kL)), one(kL + 1);
  for (double x : {-0.93, -0.2, 0.0, 0.51, 0.999}) {
    const double s = std::sqrt(1 - x * x);
    NormalizedLegendreAll(kL, x, s, all.data());
    for (int m = 0; m <= kL; ++m) {
      NormalizedLegendreOrder(kL, m, x, s, one.data());
      for (int l = m; l <= kL; ++l) EXPECT_EQ(one[l - m], all[LegendreIndex(l, m)]);
    }
  }
}

TEST(Legendre, OrthonormalUnderGaussLegendre) {
  // integral_{-1}^{1} Pbar_l^m Pbar_l'^m dx = delta / (2 pi); the products are polynomials of
  // degree <= 2L, integrated exactly by L + 1 Gauss nodes.
  constexpr int kL = 60;
  const GaussLegendreRule rule = GaussLegendre(kL + 1);
  std::vector<double> p(LegendreCount(kL));
  std::vector<double> gram(LegendreCount(kL) * (kL + 1), 0.0);
  double worst = 0;
  for (int m = 0; m <= kL; ++m) {
    std::vector<double> g((kL + 1) * (kL + 1), 0.0);
    for (size_t q = 0; q < rule.nodes.size(); ++q) {
      const double x = rule.nodes[q];
      NormalizedLegendreAll(kL, x, std::sqrt((1 - x) * (1 + x)), p.data());
      for (int l = m; l <= kL; ++l) {
        for (int l2 = m; l2 <= kL; ++l2) {
          g[l * (kL + 1) + l2] += rule.weights[q] * p[LegendreIndex(l, m)] * p[LegendreIndex(l2, m)];
        }
      }
    }
    for (int l = m; l <= kL; ++l) {
      for (int l2 = m; l2 <= kL; ++l2) {
        const double expected = l == l2 ? 1.0 / (2 * M_PI) : 0.0;
        worst = std::max(worst, std::abs(g[l * (kL + 1) + l2] - expected));
      }
    }
  }
  EXPECT_LE(worst, 1e-14);
}

TEST(Legendre, FiniteAtThePoles) {
  std::vector<double> p(LegendreCount(kMaxLegendreDegree));
  for (double x : {-1.0, 1.0}) {
    NormalizedLegendreAll(kMaxLegendreDegree, x, 0.0, p.data());
    for (int l = 0; l <= kMaxLegendreDegree; ++l) {
      // Pbar_l^0(+-1) = (+-1)^l sqrt((2l+1)/(4 pi)); all m > 0 vanish.
      EXPECT_NEAR(p[LegendreIndex(l, 0)], std::pow(x, l) * std::sqrt((2 * l + 1) / (4 * M_PI)),
                  1e-13);
      for (int m = 1; m <= l; ++m) EXPECT_EQ(p[LegendreIndex(l, m)], 0.0);
    }
  }
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
