#include "basis/quadrature.h"

#include <gtest/gtest.h>

#include <cmath>

#include "basis/error.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

TEST(GaussLegendre, MatchesTabulatedLowOrderRules) {
  const GaussLegendreRule r2 = GaussLegendre(2);
  EXPECT_NEAR(r2.nodes[1], 1 / std::sqrt(3.0), 2.3e-16);  // 2 ulps
  EXPECT_NEAR(r2.weights[0], 1.0, 1e-15);
  const GaussLegendreRule r3 = GaussLegendre(3);
  EXPECT_EQ(r3.nodes[1], 0.0);
  EXPECT_NEAR(r3.nodes[2], std::sqrt(0.6), 2.3e-16);
  EXPECT_NEAR(r3.weights[1], 8.0 / 9.0, 1e-15);
  EXPECT_NEAR(r3.weights[0], 5.0 / 9.0, 1e-15);
}

TEST(GaussLegendre, ExactForMonomialsUpToDegree2nMinus1) {
  for (int n : {1, 2, 5, 16, 31, 64, 200}) {
    const GaussLegendreRule r = GaussLegendre(n);
    double weight_sum = 0;
    for (double w : r.weights) weight_sum += w;
    EXPECT_NEAR(weight_sum, 2.0, 4e-15 * n);
    for (int k = 0; k <= std::min(2 * n - 1, 60); ++k) {
      double sum = 0;
      for (int i = 0; i < n; ++i) sum += r.weights[i] * std::pow(r.nodes[i], k);
      const double exact = k % 2 == 1 ? 0.0 : 2.0 / (k + 1);
      EXPECT_NEAR(sum, exact, 1e-14) << "n=" << n << " k=" << k;
    }
    for (int i = 0; i < n; ++i) EXPECT_EQ(r.nodes[i], -r.nodes[n - 1 - i]);
  }
}

TEST(GaussLegendre, RejectsBadSizes) {
  EXPECT_THROW(GaussLegendre(0), InputError);
}

TEST(CosThetaRules, IntegrateSmoothFunctionsOverTheZone) {
  const Zone zone = Zone::FromDegrees(9, 57);
  const double a = zone.cos_lower(), b = zone.cos_upper();
  // integral_a^b sqrt(1 - x^2) dx: not a polynomial; both rules converge to the closed form.
  auto antiderivative = [](double x) { return 0.5 * (x * std::sqrt(1 - x * x) + std::asin(x)); };
  const double exact = antiderivative(b) - antiderivative(a);
  for (const CosThetaRule& rule : {CosThetaGaussRule(zone, 40), CosThetaPsiRule(zone, 40)}) {
    double sum = 0;
    for (size_t i = 0; i < rule.x.size(); ++i) sum += rule.weight[i] * rule.s_x[i];
    EXPECT_NEAR(sum, exact, 1e-15);
    for (size_t i = 0; i < rule.x.size(); ++i) {
      EXPECT_NEAR(rule.x[i], 0.5 * (a + b) + 0.5 * (b - a) * rule.t[i], 1e-15);
      EXPECT_NEAR(rule.s_t[i] * rule.s_t[i], 1 - rule.t[i] * rule.t[i], 1e-15);
    }
  }
}

TEST(CosThetaRules, PsiRuleHandlesAZoneTouchingThePole) {
  // integral_0^1 sqrt(1-x^2) dx = pi/4 over the zone [0, 90] deg, where sqrt(1-x^2) has a
  // square-root singularity in x at the pole: Gauss in x converges slowly, Gauss in psi does
  // not (1 - x = sin^2(psi/2) (b - a)).
  const Zone zone = Zone::FromDegrees(0, 90);
  double psi_sum = 0, gauss_sum = 0;
  const CosThetaRule psi = CosThetaPsiRule(zone, 30), gauss = CosThetaGaussRule(zone, 30);
  for (size_t i = 0; i < psi.x.size(); ++i) psi_sum += psi.weight[i] * psi.s_x[i];
  for (size_t i = 0; i < gauss.x.size(); ++i) gauss_sum += gauss.weight[i] * gauss.s_x[i];
  EXPECT_NEAR(psi_sum, M_PI / 4, 1e-15);
  EXPECT_GT(std::abs(gauss_sum - M_PI / 4), 1e-6);
}

TEST(ProductRule, SolidAngleOfTheZone) {
  const Zone zone = Zone::FromDegrees(9, 57);
  const SphereRule rule = ProductRule(CosThetaGaussRule(zone, 5), 7);
  double sum = 0;
  for (size_t k = 0; k < rule.weights.size(); ++k) {
    sum += rule.weights[k];
    EXPECT_NEAR(Length(rule.directions[k]), 1.0, 1e-15);
  }
  EXPECT_NEAR(sum, zone.solid_angle_sr(), 1e-14);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
