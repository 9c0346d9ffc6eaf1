#include "basis/table_trig.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// References: long double sin, cos and atan2 (64-bit mantissa), pi to 36 digits.
constexpr long double kTwoPi = 6.283185307179586476925286766559005768L;

double SinCosError(double u) {
  double s = 0, c = 0;
  TurnSinCos(u, &s, &c);
  const long double angle = kTwoPi * static_cast<long double>(u);
  return static_cast<double>(
      std::max(std::fabs(s - std::sin(angle)), std::fabs(c - std::cos(angle))));
}

double Atan2Error(double y, double x) {
  return static_cast<double>(std::fabs(
      TableAtan2(y, x) - std::atan2(static_cast<long double>(y), static_cast<long double>(x))));
}

TEST(TableTrigTest, TurnSinCosIsWithin4e16EverywhereInTheTurn) {
  // Random points, the table's nodes and their neighbours, and both ends. 4e-16 is two units in
  // the last place of numbers near 1 (the C library's sincos of 2 pi u has the rounding of
  // 2 pi u itself on top, up to 4.4e-16 at u near 1).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) worst = std::max(worst, SinCosError(uniform(rng)));
  for (int k = 0; k <= 4096; ++k) {
    const double u = k / 4096.0;
    for (double v : {u, std::nextafter(u, 0.0), std::nextafter(u, 1.0)}) {
      if (v >= 0 && v <= 1) worst = std::max(worst, SinCosError(v));
    }
  }
  EXPECT_LT(worst, 4e-16);
  double s = 0, c = 0;
  TurnSinCos(0.25, &s, &c);
  EXPECT_EQ(s, 1.0);
  EXPECT_LT(std::fabs(c), 1e-19);  // the table's node: cos of pi / 2 in long double
}

TEST(TableTrigTest, TurnSinCosOutsideTheTurnIsTheLibrarys) {
  for (double u : {-0.3, 1.7, 12.25}) {
    double s = 0, c = 0;
    TurnSinCos(u, &s, &c);
    EXPECT_EQ(s, std::sin(2 * M_PI * u));
    EXPECT_EQ(c, std::cos(2 * M_PI * u));
  }
  double s = 0, c = 0;
  TurnSinCos(std::nan(""), &s, &c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
}

TEST(TableTrigTest, TableAtan2IsWithin6e16InEveryOctant) {
  // 6e-16 is 1.4 units in the last place of pi: the quadrant's pi - a or pi / 2 - a rounds once
  // more than the library's atan2 does.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::uniform_real_distribution<double> exponent(-30.0, 30.0);
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) {
    const double scale = std::exp2(exponent(rng));
    worst = std::max(worst, Atan2Error(scale * uniform(rng), scale * uniform(rng)));
  }
  // Ratios at the table's nodes and either side of them, the diagonals and the axes.
  for (int k = 0; k <= 256; ++k) {
    const double t = k / 256.0;
    for (double v : {t, std::nextafter(t, 0.0), std::nextafter(t, 2.0)}) {
      for (double sx : {1.0, -1.0}) {
        for (double sy : {1.0, -1.0}) {
          worst = std::max(worst, Atan2Error(sy * v, sx * 1.0));
          worst = std::max(worst, Atan2Error(sy * 1.0, sx * v));
        }
      }
    }
  }
  EXPECT_LT(worst, 6e-16);
}

TEST(TableTrigTest, TableAtan2KeepsTheLibrarysSignsAndSpecialCases) {
  const double inf = std::numeric_limits<double>::infinity();
  for (double y : {0.0, -0.0, 1.0, -1.0, inf, -inf}) {
    for (double x : {0.0, -0.0, 1.0, -1.0, inf, -inf}) {
      const double expected = std::atan2(y, x);
      const double got = TableAtan2(y, x);
      if (y == 0 || x == 0 || std::isinf(x) || std::isinf(y)) {
        EXPECT_EQ(std::signbit(got), std::signbit(expected)) << y << ", " << x;
      }
      EXPECT_NEAR(got, expected, 6e-16) << y << ", " << x;
    }
  }
  EXPECT_TRUE(std::isnan(TableAtan2(std::nan(""), 1.0)));
}

TEST(TableTrigTest, SphericalPhiMatchesTheLibrarysInEveryQuadrant) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int i = 0; i < 200000; ++i) {
    const double z = 2 * uniform(rng) - 1, phi = 2 * M_PI * uniform(rng);
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    const Vec3 w{r * std::cos(phi), r * std::sin(phi), z};
    const double got = TableSphericalPhi(w);
    EXPECT_GE(got, 0.0);
    EXPECT_LT(got, 2 * M_PI);
    // Both within an ulp or two of 2 pi of the true angle; at the wrap from 2 pi to 0 either
    // may round to the other side.
    const double diff = std::fabs(got - SphericalPhi(w));
    EXPECT_LT(std::min(diff, std::fabs(diff - 2 * M_PI)), 2e-15) << w.x << ", " << w.y;
  }
  EXPECT_EQ(TableSphericalPhi({1, 0, 0}), 0.0);
  EXPECT_NEAR(TableSphericalPhi({0, -1, 0}), 1.5 * M_PI, 1e-15);
}

TEST(TableTrigTest, ApproxAcosIsWithin13e12OverTheWholeRange) {
  // The fit's error is 1.21e-11 at its worst (an equioscillating Chebyshev fit: the extremes
  // are spread over [0, 1]); long double's acos is the reference. Random points, a fine even
  // grid, both ends and their neighbours, negative arguments through pi - acos.
  auto error = [](double z) {
    return static_cast<double>(std::fabs(ApproxAcos(z) - std::acos(static_cast<long double>(z))));
  };
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) worst = std::max(worst, error(uniform(rng)));
  for (int k = -100000; k <= 100000; ++k) worst = std::max(worst, error(k / 100000.0));
  for (double z : {1.0, -1.0, 0.0, -0.0, std::nextafter(1.0, 0.0), std::nextafter(-1.0, 0.0),
                   1e-300, 0.5, std::cos(0.001)}) {
    worst = std::max(worst, error(z));
  }
  EXPECT_LT(worst, 1.3e-11);
  EXPECT_GT(worst, 1e-13);  // a fit, not the library: the bound above is the one that holds
  EXPECT_EQ(ApproxAcos(1.0), 0.0);
  // Outside [-1, 1] as SphericalTheta (which clamps); NaN stays NaN.
  EXPECT_EQ(ApproxAcos(1.5), 0.0);
  EXPECT_NEAR(ApproxAcos(-3.0), M_PI, 1.3e-11);
  EXPECT_TRUE(std::isnan(ApproxAcos(std::nan(""))));
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
