#include "basis/spherical_harmonics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "basis/legendre.h"
#include "basis/quadrature.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

Vec3 RandomDirection(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  const double z = 2 * u(rng) - 1, phi = 2 * M_PI * u(rng);
  const double r = std::sqrt(1 - z * z);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

TEST(SphericalHarmonics, IndexRoundTrip) {
  for (int k = 0; k < ShCount(30); ++k) {
    int l, m;
    ShDegreeOrder(k, &l, &m);
    EXPECT_EQ(ShIndex(l, m), k);
    EXPECT_LE(std::abs(m), l);
  }
}

TEST(SphericalHarmonics, MatchesCartesianClosedFormsUpToDegree2) {
  // Real SH with the Condon-Shortley phase, e.g. Sloan 2008 "Stupid SH tricks" table with the
  // (-1)^m sign applied.
  std::mt19937_64 rng(7);
  std::vector<double> y(ShCount(2));
  for (int i = 0; i < 200; ++i) {
    const Vec3 w = RandomDirection(rng);
    const double x = w.x, yy = w.y, z = w.z;
    EvalShAll(2, w, y.data());
    const double c0 = 0.5 / std::sqrt(M_PI), c1 = std::sqrt(3 / (4 * M_PI));
    const double c2 = 0.5 * std::sqrt(15 / M_PI), c20 = 0.25 * std::sqrt(5 / M_PI);
    const double expected[9] = {c0,      -c1 * yy, c1 * z, -c1 * x,
                                c2 * x * yy, -c2 * yy * z, c20 * (3 * z * z - 1), -c2 * x * z,
                                0.5 * c2 * (x * x - yy * yy)};
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(y[k], expected[k], 1e-15) << k;
  }
}

TEST(SphericalHarmonics, AdditionTheoremHoldsUpToDegree60) {
  // sum_m Y_lm(a) Y_lm(b) = (2l+1)/(4 pi) P_l(a.b): an identity the per-function evaluation does
  // not use, checked at every degree.
  constexpr int kL = 60;
  std::mt19937_64 rng(11);
  std::vector<double> ya(ShCount(kL)), yb(ShCount(kL));
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 a = RandomDirection(rng), b = RandomDirection(rng);
    EvalShAll(kL, a, ya.data());
    EvalShAll(kL, b, yb.data());
    const double c = Dot(a, b);
    std::vector<double> legendre_p(kL + 1);  // P_l(c) by Bonnet's recurrence
    legendre_p[0] = 1;
    legendre_p[1] = c;
    for (int l = 1; l < kL; ++l) {
      legendre_p[l + 1] = ((2 * l + 1) * c * legendre_p[l] - l * legendre_p[l - 1]) / (l + 1);
    }
    for (int l = 0; l <= kL; ++l) {
      double sum = 0;
      for (int m = -l; m <= l; ++m) sum += ya[ShIndex(l, m)] * yb[ShIndex(l, m)];
      // Terms are O((2l+1)/(4 pi)); rounding of 2l+1 terms of that size.
      EXPECT_NEAR(sum, (2 * l + 1) / (4 * M_PI) * legendre_p[l], 1e-14 * (2 * l + 1)) << "l=" << l;
    }
  }
}

TEST(SphericalHarmonics, OrthonormalOverTheSphere) {
  constexpr int kL = 20;
  const GaussLegendreRule gl = GaussLegendre(kL + 1);
  const int n_phi = 2 * kL + 1;
  std::vector<double> y(ShCount(kL));
  std::vector<double> gram(ShCount(kL) * ShCount(kL), 0.0);
  for (size_t i = 0; i < gl.nodes.size(); ++i) {
    const double z = gl.nodes[i], r = std::sqrt((1 - z) * (1 + z));
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2 * M_PI * j / n_phi;
      EvalShAll(kL, {r * std::cos(phi), r * std::sin(phi), z}, y.data());
      const double w = gl.weights[i] * 2 * M_PI / n_phi;
      for (int a = 0; a < ShCount(kL); ++a) {
        for (int b = 0; b < ShCount(kL); ++b) gram[a * ShCount(kL) + b] += w * y[a] * y[b];
      }
    }
  }
  double worst = 0;
  for (int a = 0; a < ShCount(kL); ++a) {
    for (int b = 0; b < ShCount(kL); ++b) {
      worst = std::max(worst, std::abs(gram[a * ShCount(kL) + b] - (a == b ? 1.0 : 0.0)));
    }
  }
  EXPECT_LE(worst, 1e-13);
}

TEST(SphericalHarmonics, PoleIsWellDefined) {
  std::vector<double> y(ShCount(10));
  EvalShAll(10, {0, 0, 1}, y.data());
  for (int l = 0; l <= 10; ++l) {
    for (int m = -l; m <= l; ++m) {
      if (m != 0) EXPECT_EQ(y[ShIndex(l, m)], 0.0);
      else EXPECT_NEAR(y[ShIndex(l, 0)], std::sqrt((2 * l + 1) / (4 * M_PI)), 1e-14);
    }
  }
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
