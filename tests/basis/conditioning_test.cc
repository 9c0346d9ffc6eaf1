#include "basis/conditioning.h"

#include <gtest/gtest.h>

#include "basis/error.h"
#include "basis/zone.h"

namespace zbrdf {
namespace {

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

}  // namespace
}  // namespace zbrdf
