#include "basis/conversion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "basis/conditioning.h"
#include "basis/error.h"
#include "basis/gram.h"
#include "basis/quadrature.h"
#include "basis/spherical_harmonics.h"
#include "tests/basis/basis_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::RandomCoefficients;

// ZB moments z_j = integral_Z f Z_j dw of f = sum_i y_i T_i, by direct quadrature of the
// functions (not through MixedBlock): Gauss in psi x trapezoid in phi, with node counts well
// beyond what the integrands' degrees need.
Eigen::VectorXd MomentsByQuadrature(const ZonalBasis& zb, const TargetBasis& target,
                                    const Eigen::VectorXd& y) {
  const int degree = zb.order() + target.order();
  const SphereRule rule = ProductRule(CosThetaPsiRule(zb.zone(), 2 * degree + 60), 2 * degree + 3);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(zb.size());
  std::vector<double> t(target.size()), zv(zb.size());
  for (size_t q = 0; q < rule.weights.size(); ++q) {
    target.Eval(rule.directions[q], t.data());
    zb.Eval(rule.directions[q], zv.data());
    double f = 0;
    for (int i = 0; i < target.size(); ++i) f += y(i) * t[i];
    for (int j = 0; j < zb.size(); ++j) z(j) += rule.weights[q] * f * zv[j];
  }
  return z;
}

// Relative L2 error of sum (y_est - y) T over the theta range [lo, hi] (degrees), by the
// library's ErrorOverBand (tested against independent references in conditioning_test.cc).
double RelativeError(const TargetBasis& target, const Eigen::VectorXd& y,
                     const Eigen::VectorXd& y_est, double lo_deg, double hi_deg) {
  return ErrorOverBand(target, y, y_est, DegToRad(lo_deg), DegToRad(hi_deg)).Relative();
}

struct RoundTrip {
  double in_zone, outside;
};

RoundTrip MeasureRoundTrip(const Zone& zone, int order, TargetKind kind, uint64_t seed) {
  const ZonalBasis zb(zone, order);
  const TargetBasis target(kind, order);
  const ZonalToTarget conversion(zb, target);
  const Eigen::VectorXd y = RandomCoefficients(target.size(), seed);
  const Eigen::VectorXd y_est = conversion.Apply(MomentsByQuadrature(zb, target, y));
  const double min_deg = RadToDeg(zone.theta_min_rad()), max_deg = RadToDeg(zone.theta_max_rad());
  RoundTrip r;
  r.in_zone = RelativeError(target, y, y_est, min_deg, max_deg);
  // Outside: the polar cap and the band below the horizon-side edge, combined by their worst.
  r.outside = std::max(RelativeError(target, y, y_est, 0, min_deg),
                       RelativeError(target, y, y_est, max_deg, 90));
  return r;
}

TEST(Conversion, RoundTripInTheBuiltZoneUpToOrder10) {
  for (int order = 1; order <= 10; ++order) {
    const RoundTrip r = MeasureRoundTrip(Zone::FromDegrees(9, 57), order, TargetKind::kSh, order);
    EXPECT_LE(r.in_zone, 1e-12) << "order " << order;
  }
}

TEST(Conversion, RoundTripInTheDesignedZoneUpToOrder14) {
  for (int order : {2, 6, 10, 12, 14}) {
    const RoundTrip r = MeasureRoundTrip(Zone::FromDegrees(9, 90), order, TargetKind::kSh, order);
    EXPECT_LE(r.in_zone, 1e-12) << "order " << order;
  }
}

TEST(Conversion, ParitySphericalHarmonicsRecoverTheCapOutsideTheDesignedZone) {
  for (TargetKind kind : {TargetKind::kShEven, TargetKind::kShOdd}) {
    for (int order : {2, 6, 10, 14}) {
      const RoundTrip r = MeasureRoundTrip(Zone::FromDegrees(9, 90), order, kind, 100 + order);
      EXPECT_LE(r.in_zone, 1e-12) << TargetName(kind) << " order " << order;
      EXPECT_LE(r.outside, 1e-12) << TargetName(kind) << " order " << order;
    }
  }
}

TEST(Conversion, HemisphericalHarmonicsOfTheHemisphereZoneAreTheIdentity) {
  const ZonalBasis zb(Zone::FromDegrees(0, 90), 8);
  const ZonalToTarget conversion(zb, TargetBasis(TargetKind::kHsh, 8));
  EXPECT_LE((conversion.matrix() - Eigen::MatrixXd::Identity(zb.size(), zb.size()))
                .cwiseAbs()
                .maxCoeff(),
            1e-14);
  EXPECT_NEAR(conversion.diagnostics().noise_gain, 1.0, 1e-13);
}

TEST(Conversion, TheThesisDualFormulaIsBiased) {
  // Regression guard (docs/design.md section 3, item 2): y = G^-1 B z, with G the SH Gram matrix on
  // the zone and B = integral Y Z, errs by far more than the moment form even without noise.
  const Zone zone = Zone::FromDegrees(9, 57);
  constexpr int kOrder = 4;
  const ZonalBasis zb(zone, kOrder);
  const TargetBasis sh(TargetKind::kSh, kOrder);
  const Eigen::VectorXd y = RandomCoefficients(sh.size(), 5);
  const Eigen::VectorXd z = MomentsByQuadrature(zb, sh, y);
  Eigen::VectorXd y_dual = Eigen::VectorXd::Zero(sh.size());
  for (int m = 0; m <= kOrder; ++m) {
    const Eigen::MatrixXd g = TargetGramBlock(sh, zone, m);
    const Eigen::MatrixXd b = MixedBlock(sh, zb, m, DefaultPsiNodes(kOrder, kOrder));
    for (int sign : {+1, -1}) {
      if (m == 0 && sign < 0) continue;
      Eigen::VectorXd zm(kOrder - m + 1);
      for (int j = 0; j <= kOrder - m; ++j) zm(j) = z(ShIndex(m + j, sign * m));
      const Eigen::VectorXd ym = g.fullPivLu().solve(b * zm);
      for (int i = 0; i <= kOrder - m; ++i) y_dual(ShIndex(m + i, sign * m)) = ym(i);
    }
  }
  EXPECT_GT(RelativeError(sh, y, y_dual, 9, 57), 1e-2);
  const ZonalToTarget moment_form(zb, sh);
  EXPECT_LE(RelativeError(sh, y, moment_form.Apply(z), 9, 57), 1e-12);
}

TEST(Conversion, TensorProductRecoversBandLimitedBrdfCoefficients) {
  // f(w_i, w_r) = sum_ab Y_ab T_a(w_i) T_b(w_r) with sh-even on [9, 90] (well conditioned), so
  // the coefficients themselves come back, not only the function in the zone.
  const Zone zone = Zone::FromDegrees(9, 90);
  constexpr int kOrder = 4;
  const ZonalBasis zb(zone, kOrder);
  const TargetBasis even(TargetKind::kShEven, kOrder);
  const ZonalToTarget conversion(zb, even);
  const int n = even.size();
  Eigen::MatrixXd y(n, n);
  std::mt19937_64 rng(17);
  std::normal_distribution<double> normal(0, 1);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) y(i, j) = normal(rng);
  }
  // z_kj = integral integral Z_k(w_i) Z_j(w_r) f dw_i dw_r: the tensor of per-direction moments.
  Eigen::MatrixXd half(zb.size(), n);  // moments in w_i of each column's function
  for (int b = 0; b < n; ++b) half.col(b) = MomentsByQuadrature(zb, even, y.col(b));
  Eigen::MatrixXd z(zb.size(), zb.size());
  for (int k = 0; k < zb.size(); ++k) {
    z.row(k) = MomentsByQuadrature(zb, even, half.row(k).transpose()).transpose();
  }
  const Eigen::MatrixXd y_est = ConvertTensor(conversion, conversion, z);
  EXPECT_LE((y_est - y).cwiseAbs().maxCoeff(), 1e-12 * y.cwiseAbs().maxCoeff());
  EXPECT_THROW(ConvertTensor(conversion, conversion, Eigen::MatrixXd(3, 3)), InputError);
}

TEST(Conversion, DiagnosticsDescribeTheMatrix) {
  const ZonalBasis zb(Zone::FromDegrees(9, 57), 6);
  const TargetBasis sh(TargetKind::kSh, 6);
  const ZonalToTarget exact(zb, sh, 0.0);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(exact.matrix());
  EXPECT_NEAR(exact.diagnostics().noise_gain / svd.singularValues()(0), 1.0, 1e-10);
  EXPECT_EQ(exact.diagnostics().truncated_components, 0);
  EXPECT_EQ(static_cast<int>(exact.diagnostics().singular_values.size()), sh.size());
  // The moment matrix is the conversion's (pseudo-)inverse.
  EXPECT_LE((exact.matrix() * exact.moment_matrix() - Eigen::MatrixXd::Identity(sh.size(), sh.size()))
                .cwiseAbs()
                .maxCoeff(),
            1e-6);
  int previous = 0;
  for (double tau : {1e-12, 1e-8, 1e-4, 1e-2}) {
    const ZonalToTarget truncated(zb, sh, tau);
    EXPECT_GE(truncated.diagnostics().truncated_components, previous);
    previous = truncated.diagnostics().truncated_components;
    EXPECT_LE(truncated.diagnostics().noise_gain, exact.diagnostics().noise_gain * (1 + 1e-12));
    EXPECT_GE(truncated.diagnostics().smallest_kept_singular_value,
              tau * truncated.diagnostics().largest_singular_value);
  }
  EXPECT_GT(previous, 0);
  EXPECT_THROW(ZonalToTarget(zb, sh, -1), InputError);
  EXPECT_THROW(ZonalToTarget(zb, sh, 1.5), InputError);
  EXPECT_THROW(ZonalToTarget(zb, sh, NAN), InputError);
}

TEST(Conversion, FactoredApplicationReproducesTheMomentsAtHighOrder) {
  // Backward stability: the converted coefficients reproduce the data they came from, to
  // rounding, even where the smallest singular value is ~3e-12 (order 10 on [9, 57] deg).
  // The explicit matrix product does not: it is kept for inspection only.
  const ZonalBasis zb(Zone::FromDegrees(9, 57), 10);
  const TargetBasis sh(TargetKind::kSh, 10);
  const ZonalToTarget conversion(zb, sh);
  const Eigen::VectorXd z = MomentsByQuadrature(zb, sh, RandomCoefficients(sh.size(), 23));
  const Eigen::VectorXd y = conversion.Apply(z);
  EXPECT_LE((conversion.moment_matrix() * y - z).norm(), 1e-14 * z.norm());
  const Eigen::VectorXd y_explicit = conversion.matrix() * z;
  EXPECT_GT((conversion.moment_matrix() * y_explicit - z).norm(), 1e-12 * z.norm());
  EXPECT_THROW(conversion.Apply(Eigen::VectorXd::Zero(5)), InputError);
}

TEST(Conversion, HigherTargetOrderThanDataIsReportedAsUnderdetermined) {
  const ZonalBasis zb(Zone::FromDegrees(9, 57), 4);
  const ZonalToTarget conversion(zb, TargetBasis(TargetKind::kSh, 6));
  // |m| = 5 and 6 have no ZB partner: (2 + 1) functions, each for +-m: 6. For |m| <= 4 the two
  // degrees 5 and 6 exceed the data: 2 (m = 0) + 4 * 2 * 2 = 18.
  EXPECT_EQ(conversion.diagnostics().underdetermined_components, 6 + 18);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
