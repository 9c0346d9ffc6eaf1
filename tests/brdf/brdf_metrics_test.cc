// The cosine-weighted L2 distance between BRDFs, against closed forms.
#include "brdf/brdf_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "brdf/material_spec.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// For f_a - f_b = d (constant over the hemisphere pairs):
//   (1 / (2 pi)^2) integral integral d^2 cos^2(theta_i) dw_i dw_o = d^2 (2 pi / 3)(2 pi) / (2 pi)^2
// so E = |d| / sqrt(3).
double ConstantDifferenceDistance(double d) { return std::abs(d) / std::sqrt(3.0); }

TEST(CosineWeightedL2, TwoLambertiansMatchTheClosedForm) {
  const auto a = MakeBrdf("lambert:0.8,0.5,0.2"), b = MakeBrdf("lambert:0.5,0.5,0.6");
  const BrdfDistance d = CosineWeightedL2(*a, *b, 1 << 16, 3);
  const double expected[3] = {ConstantDifferenceDistance(0.3 / M_PI), 0.0,
                              ConstantDifferenceDistance(0.4 / M_PI)};
  for (int c = 0; c < 3; ++c) {
    // 5 standard errors (the estimator's own), plus 1e-15 for the exact zero.
    EXPECT_NEAR(d.l2[c], expected[c], 5 * d.l2_standard_error[c] + 1e-15) << c;
    EXPECT_LT(d.l2_standard_error[c], 0.01 * expected[c] + 1e-15);
  }
  EXPECT_NEAR(d.reference_norm.r, ConstantDifferenceDistance(0.8 / M_PI), 0.01 * 0.8 / M_PI);
}

TEST(CosineWeightedL2, GlossyModelsDifferingByALambertianTerm) {
  // ggx with kd minus the same ggx without: the difference is kd / pi everywhere, which the
  // estimator must find although it samples both glossy lobes.
  const auto a = MakeBrdf("ggx:alpha=0.1,F0=0.9,kd=0.3"), b = MakeBrdf("ggx:alpha=0.1,F0=0.9");
  const BrdfDistance d = CosineWeightedL2(*a, *b, 1 << 17, 5);
  EXPECT_NEAR(d.Mean(), ConstantDifferenceDistance(0.3 / M_PI), 5 * d.l2_standard_error.r);
  const BrdfDistance same = CosineWeightedL2(*b, *b, 1 << 12, 5);
  EXPECT_EQ(same.Mean(), 0.0);
  EXPECT_EQ(same.RelativeMean(), 0.0);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
