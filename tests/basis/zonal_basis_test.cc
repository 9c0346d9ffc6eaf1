#include "basis/zonal_basis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "basis/error.h"
#include "basis/gram.h"
#include "basis/legendre.h"
#include "tests/basis/reference_legendre.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

double MaxDeviationFromIdentity(const Eigen::MatrixXd& g) {
  return (g - Eigen::MatrixXd::Identity(g.rows(), g.cols())).cwiseAbs().maxCoeff();
}

struct ZoneCase {
  double min_deg, max_deg;
};
const ZoneCase kZones[] = {{9, 57}, {9, 90}, {0, 90}};

TEST(ZonalBasis, OrthonormalWithLPlusOneByTwoLPlusOneNodesUpToOrder30) {
  for (const ZoneCase& zc : kZones) {
    for (int order : {0, 1, 2, 4, 8, 10, 14, 20, 30}) {
      const ZonalBasis zb(Zone::FromDegrees(zc.min_deg, zc.max_deg), order);
      const Eigen::MatrixXd g = ZonalGramByQuadrature(zb, order + 1, 2 * order + 1);
      // Entries are sums of (L+1)(2L+1) products of O(1) terms (normalized functions).
      EXPECT_LE(MaxDeviationFromIdentity(g), 1e-13)
          << "zone [" << zc.min_deg << ", " << zc.max_deg << "] order " << order;
    }
  }
}

TEST(ZonalBasis, LNodesInThetaAreNotEnough) {
  // With L nodes in cos(theta) the rule is exact only to degree 2L - 1 in t, but Z_L0^2 has
  // degree 2L: the Gram matrix is visibly wrong.
  for (const ZoneCase& zc : kZones) {
    for (int order : {2, 6, 10}) {
      const ZonalBasis zb(Zone::FromDegrees(zc.min_deg, zc.max_deg), order);
      EXPECT_GT(MaxDeviationFromIdentity(ZonalGramByQuadrature(zb, order, 2 * order + 1)), 1e-3);
      // And with 2L trapezoid points in phi the cos(L phi)^2 / sin(L phi)^2 pair aliases.
      EXPECT_GT(MaxDeviationFromIdentity(ZonalGramByQuadrature(zb, order + 1, 2 * order)), 1e-3);
    }
  }
}

TEST(ZonalBasis, MatchesTheThesisFormulaForLowOrders) {
  // Ghosh 2007 eq. 3.9-3.11 with unnormalized P_l^m and the factorial constant K^_l^m.
  const Zone zone = Zone::FromDegrees(9, 57);
  const ZonalBasis zb(zone, 3);
  const double n1 = 2 / (zone.cos_upper() - zone.cos_lower());
  const double n2 = 2 * zone.cos_upper() / (zone.cos_upper() - zone.cos_lower()) - 1;
  auto fact = [](int n) { return std::tgamma(n + 1.0); };
  auto p_unnormalized = [](int l, int m, double x) {
    const double s = std::sqrt(1 - x * x);
    const double table[4][4] = {
        {1, 0, 0, 0},
        {x, -s, 0, 0},
        {0.5 * (3 * x * x - 1), -3 * x * s, 3 * s * s, 0},
        {0.5 * (5 * x * x * x - 3 * x), -1.5 * (5 * x * x - 1) * s, 15 * x * s * s,
         -15 * s * s * s}};
    return table[l][m];
  };
  std::vector<double> z(zb.size());
  for (double theta_deg = 9.5; theta_deg < 57; theta_deg += 3.1) {
    for (double phi = 0.1; phi < 6.2; phi += 0.9) {
      const double x = std::cos(DegToRad(theta_deg));
      zb.Eval(x, phi, z.data());
      for (int l = 0; l <= 3; ++l) {
        for (int m = -l; m <= l; ++m) {
          const int am = std::abs(m);
          const double k_hat =
              std::sqrt((2 * l + 1) * fact(l - am) /
                        (2 * M_PI * (zone.cos_upper() - zone.cos_lower()) * fact(l + am)));
          const double p = p_unnormalized(l, am, n1 * x - n2);
          const double expected = m == 0 ? k_hat * p
                                  : m > 0 ? std::sqrt(2.0) * k_hat * std::cos(m * phi) * p
                                          : std::sqrt(2.0) * k_hat * std::sin(-m * phi) * p;
          EXPECT_NEAR(z[ShIndex(l, m)], expected, 1e-13) << l << " " << m;
        }
      }
    }
  }
}

TEST(ZonalBasis, HemisphereZoneIsTheHemisphericalHarmonics) {
  // Gautron et al. 2004: H_lm(theta, phi) = sqrt(2) Y_lm(arccos(2 cos theta - 1), phi).
  const ZonalBasis zb(Zone::FromDegrees(0, 90), 12);
  std::vector<double> z(zb.size()), y(zb.size());
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 300; ++i) {
    const double x = u(rng), phi = 2 * M_PI * u(rng);
    zb.Eval(x, phi, z.data());
    EvalShAll(12, SphericalDirection(std::acos(2 * x - 1), phi), y.data());
    for (int k = 0; k < zb.size(); ++k) EXPECT_NEAR(z[k], std::sqrt(2.0) * y[k], 2e-13);
  }
}

TEST(ZonalBasis, AccurateAndFiniteAtAndNearTheZoneEdges) {
  // Reference: the same map to the virtual sphere in long double, with 1 - t and 1 + t formed
  // from the edges, and the long-double Legendre reference. A naive sqrt(1 - t^2) in double
  // would lose ~7 digits 1e-9 rad from an edge, where 1 - t ~ 1e-9.
  for (const ZoneCase& zc : kZones) {
    const Zone zone = Zone::FromDegrees(zc.min_deg, zc.max_deg);
    const ZonalBasis zb(zone, 30);
    const long double a = zone.cos_lower(), b = zone.cos_upper();
    std::vector<double> z(LegendreCount(30));
    double worst = 0;
    for (double edge : {zone.theta_min_rad(), zone.theta_max_rad()}) {
      const double inward = edge == zone.theta_min_rad() ? 1.0 : -1.0;
      for (double offset : {0.0, 1e-12, 1e-11, 1e-10, 3e-10, 1e-9}) {
        const double x = std::cos(edge + inward * offset);
        zb.EvalThetaPart(x, z.data());
        const long double one_minus_t = 2 * (b - x) / (b - a), one_plus_t = 2 * (x - a) / (b - a);
        const long double t = one_minus_t < one_plus_t ? 1 - one_minus_t : one_plus_t - 1;
        const long double s = std::sqrt(one_minus_t * one_plus_t);
        for (int l = 0; l <= 30; ++l) {
          for (int m = 0; m <= l; ++m) {
            const double value = z[LegendreIndex(l, m)];
            ASSERT_TRUE(std::isfinite(value));
            const double reference = static_cast<double>(
                std::sqrt(2 / (b - a)) * testing::ReferencePbar(l, m, t, s));
            worst = std::max(worst, std::abs(value - reference));
          }
        }
      }
    }
    // Values are O(sqrt(2/(b-a)) * 3) <= 7; a few ulps of that.
    EXPECT_LE(worst, 1e-14 * zb.normalization()) << zone.ToString();
  }
}

TEST(ZonalBasis, ZeroOutsideTheZone) {
  const ZonalBasis zb(Zone::FromDegrees(9, 57), 6);
  std::vector<double> z(zb.size());
  for (double theta_deg : {0.0, 8.99, 57.01, 89.0, 120.0}) {
    zb.Eval(SphericalDirection(DegToRad(theta_deg), 1.0), z.data());
    for (double v : z) EXPECT_EQ(v, 0.0) << theta_deg;
  }
}

TEST(ZonalBasis, RejectsBadZonesAndOrders) {
  EXPECT_THROW(Zone::FromDegrees(57, 9), InputError);
  EXPECT_THROW(Zone::FromDegrees(-1, 9), InputError);
  EXPECT_THROW(Zone::FromDegrees(10, 95), InputError);
  EXPECT_THROW(Zone(0.1, NAN), InputError);
  EXPECT_THROW(ZonalBasis(Zone::FromDegrees(9, 57), 61), InputError);
  EXPECT_THROW(ZonalBasis(Zone::FromDegrees(9, 57), -1), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
