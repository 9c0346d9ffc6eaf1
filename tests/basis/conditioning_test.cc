#include "basis/conditioning.h"

#include <gtest/gtest.h>

#include <cmath>

#include "basis/error.h"
#include "basis/gram.h"
#include "basis/spherical_harmonics.h"
#include "basis/zone.h"
#include "tests/basis/basis_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

ConditioningOptions Options(double min_deg, double max_deg, int order, TargetKind target) {
  ConditioningOptions o;
  o.theta_min_rad = DegToRad(min_deg);
  o.theta_max_rad = DegToRad(max_deg);
  o.zb_order = order;
  o.target_order = order;
  o.target = target;
  return o;
}

TEST(Conditioning, BuiltZoneReportWarnsAboutExtrapolation) {
  const ConditioningReport r = AnalyzeConditioning(Options(9, 57, 8, TargetKind::kSh));
  EXPECT_EQ(r.zb_size, 81);
  EXPECT_LE(r.zb_orthonormality_max_error, 1e-13);
  // Shannon number (L+1)^2 (b-a)/2 in closed form.
  const double expected = 81 * (std::cos(DegToRad(9)) - std::cos(DegToRad(57))) / 2;
  EXPECT_NEAR(r.shannon_number, expected, 1e-12 * expected);
  ASSERT_EQ(r.gram_condition_per_m.size(), 9u);
  // Beyond 1/eps at |m| = 0 (docs/design.md section 3, item 1: 2.5e18 at L = 8).
  EXPECT_TRUE(r.gram_condition_saturated[0]);
  EXPECT_NEAR(r.gram_condition_per_m[8], 1.0, 1e-12);  // a single function per block
  EXPECT_LE(r.roundtrip_error_in_zone, 1e-12);
  EXPECT_GT(r.noise_gain, 1e8);
  EXPECT_GT(r.noisy_roundtrip_error_outside_zone, 1.0);  // extrapolation is noise
  EXPECT_EQ(r.warnings.size(), 2u);                       // extrapolation and noise gain
}

TEST(Conditioning, DesignedZoneWithParityTargetIsClean) {
  const ConditioningReport r = AnalyzeConditioning(Options(9, 90, 10, TargetKind::kShEven));
  EXPECT_LE(r.roundtrip_error_in_zone, 1e-12);
  EXPECT_LE(r.roundtrip_error_outside_zone, 1e-12);
  EXPECT_LT(r.noise_gain, 10);
  // 1e-3 noise stays ~1e-3 (times the small noise gain) everywhere.
  EXPECT_LT(r.noisy_roundtrip_error_outside_zone, 1e-2);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(Conditioning, HemisphereZoneHasNothingOutside) {
  const ConditioningReport r = AnalyzeConditioning(Options(0, 90, 6, TargetKind::kHsh));
  EXPECT_FALSE(r.has_outside);
  EXPECT_NEAR(r.noise_gain, 1.0, 1e-12);
  EXPECT_LE(r.roundtrip_error_in_zone, 1e-13);
}

TEST(Conditioning, LargeTauTruncatesAndLowersTheNoiseGain) {
  ConditioningOptions o = Options(9, 57, 8, TargetKind::kSh);
  const ConditioningReport exact = AnalyzeConditioning(o);
  o.tau = 1e-4;
  const ConditioningReport truncated = AnalyzeConditioning(o);
  EXPECT_GT(truncated.truncated_components, 0);
  EXPECT_LE(truncated.noise_gain, 1e4 / truncated.largest_singular_value * (1 + 1e-12));
  EXPECT_LT(truncated.noise_gain, exact.noise_gain);
  // Truncation costs accuracy on noise-free data, buys it on noisy data.
  EXPECT_GT(truncated.roundtrip_error_in_zone, exact.roundtrip_error_in_zone);
  EXPECT_LT(truncated.noisy_roundtrip_error_outside_zone, exact.noisy_roundtrip_error_outside_zone);
}

TEST(Conditioning, RejectsBadOptions) {
  EXPECT_THROW(AnalyzeConditioning(Options(57, 9, 4, TargetKind::kSh)), InputError);
  ConditioningOptions o = Options(9, 57, 4, TargetKind::kSh);
  o.tau = -1;
  EXPECT_THROW(AnalyzeConditioning(o), InputError);
  o = Options(9, 57, 70, TargetKind::kSh);
  EXPECT_THROW(AnalyzeConditioning(o), InputError);
}

using testing::RandomCoefficients;

// integral over the band of (sum_i d_i T_i)^2 by the Gram blocks (basis/gram.h: Gauss-Legendre
// in cos theta per |m|, the azimuthal integral done analytically): a second method, sharing no
// quadrature with ErrorOverBand's product rule.
double SquaredNormByGram(const TargetBasis& target, const Eigen::VectorXd& d, const Zone& band) {
  double sum = 0;
  for (int m = 0; m <= target.order(); ++m) {
    const std::vector<int> degrees = target.DegreesForOrder(m);
    if (degrees.empty()) continue;
    const Eigen::MatrixXd g = TargetGramBlock(target, band, m);
    for (int sign : {+1, -1}) {
      if (m == 0 && sign < 0) continue;
      Eigen::VectorXd dm(degrees.size());
      for (size_t k = 0; k < degrees.size(); ++k) dm(k) = d(target.Index(degrees[k], sign * m));
      sum += dm.dot(g * dm);
    }
  }
  return sum;
}

TEST(ErrorOverBand, ParityHarmonicsOnTheHemisphereFollowParseval) {
  // SH with l + m even are even under z -> -z, so over the upper hemisphere their inner
  // products are half those over the sphere: integral f^2 = |y|^2 / 2, exactly.
  const TargetBasis target(TargetKind::kShEven, 8);
  const Eigen::VectorXd y = RandomCoefficients(target.size(), 3);
  const Eigen::VectorXd y_est = y + 1e-3 * RandomCoefficients(target.size(), 4);
  const BandError e = ErrorOverBand(target, y, y_est, 0.0, M_PI / 2);
  EXPECT_NEAR(e.norm_sq, y.squaredNorm() / 2, 1e-13 * y.squaredNorm());
  EXPECT_NEAR(e.error_sq, (y_est - y).squaredNorm() / 2, 1e-12 * (y_est - y).squaredNorm());
  EXPECT_NEAR(e.Relative(), (y_est - y).norm() / y.norm(), 1e-12);
}

TEST(ErrorOverBand, AgreesWithTheGramMatrixOnAZone) {
  const Zone band = Zone::FromDegrees(9, 57);
  const TargetBasis target(TargetKind::kSh, 6);
  const Eigen::VectorXd y = RandomCoefficients(target.size(), 5);
  const Eigen::VectorXd y_est = y + 0.01 * RandomCoefficients(target.size(), 6);
  const BandError e = ErrorOverBand(target, y, y_est, band.theta_min_rad(), band.theta_max_rad());
  const double norm_sq = SquaredNormByGram(target, y, band);
  const double error_sq = SquaredNormByGram(target, y_est - y, band);
  // Both rules are exact for these polynomials: rounding only.
  EXPECT_NEAR(e.norm_sq, norm_sq, 1e-12 * norm_sq);
  EXPECT_NEAR(e.error_sq, error_sq, 1e-10 * error_sq);
  EXPECT_NEAR(e.Relative(), std::sqrt(error_sq / norm_sq), 1e-10);
}

TEST(ErrorOverBand, EmptyBandsAndVanishingFunctionsGiveZero) {
  const TargetBasis target(TargetKind::kSh, 2);
  const Eigen::VectorXd y = RandomCoefficients(target.size(), 7);
  const BandError empty = ErrorOverBand(target, y, 2 * y, 0.3, 0.3);
  EXPECT_EQ(empty.norm_sq, 0);
  EXPECT_EQ(empty.Relative(), 0);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(target.size());
  EXPECT_EQ(ErrorOverBand(target, zero, y, 0.1, 1.0).Relative(), 0);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
