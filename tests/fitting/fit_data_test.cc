#include "fitting/fit_data.h"

#include <gtest/gtest.h>

#include "basis/spherical_harmonics.h"
#include "brdf/ggx.h"
#include "fitting/fit_quadrature.h"
#include "tests/fitting/fit_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

const Zone kZone = Zone::FromDegrees(11.3, 54.9);

TEST(IsotropicLayoutTest, IndexesEveryBlockEntryOnceAndExpandsToTheBlocks) {
  const int order = 4;
  const IsotropicLayout layout(order);
  int expected_size = 0;
  for (int m = 0; m <= order; ++m) expected_size += (order + 1 - m) * (order + 1 - m);
  ASSERT_EQ(layout.size(), expected_size);
  std::vector<int> seen(layout.size(), 0);
  for (int m = 0; m <= order; ++m) {
    for (int l = m; l <= order; ++l) {
      for (int lp = m; lp <= order; ++lp) ++seen[layout.Index(m, l, lp)];
    }
  }
  for (int count : seen) EXPECT_EQ(count, 1);
  Eigen::VectorXd v(layout.size());
  for (int i = 0; i < v.size(); ++i) v[i] = i + 1;
  const Eigen::MatrixXd full = layout.Expand(v);
  // (l, m), (l', m') entries: the block value for m' = m (both signs), else 0.
  for (int k = 0; k < full.rows(); ++k) {
    int l, m;
    ShDegreeOrder(k, &l, &m);
    for (int j = 0; j < full.cols(); ++j) {
      int lp, mp;
      ShDegreeOrder(j, &lp, &mp);
      const double expected = mp == m ? v[layout.Index(std::abs(m), l, lp)] : 0.0;
      EXPECT_EQ(full(k, j), expected) << k << "," << j;
    }
  }
}

TEST(IsotropicCoefficientsTest, PoolsPlusAndMinusMByInverseVariance) {
  const int order = 2;
  ZonalTensor data;
  data.theta_min_rad = kZone.theta_min_rad();
  data.theta_max_rad = kZone.theta_max_rad();
  data.order = order;
  const int n = ShCount(order);
  for (int ch = 0; ch < 3; ++ch) {
    data.z[ch] = Eigen::MatrixXd::Zero(n, n);
    data.variance[ch] = Eigen::MatrixXd::Ones(n, n);
  }
  // (l=1, m=1), (l'=2, m=1): +m copy 1.0 with variance 1, -m copy 4.0 with variance 3.
  data.z[0](ShIndex(1, 1), ShIndex(2, 1)) = 1.0;
  data.z[0](ShIndex(1, -1), ShIndex(2, -1)) = 4.0;
  data.variance[0](ShIndex(1, -1), ShIndex(2, -1)) = 3.0;
  const IsotropicData iso = IsotropicCoefficients(data);
  const int i = iso.layout.Index(1, 1, 2);
  // Weights 1 and 1/3: mean (1 + 4/3) / (4/3) = 1.75, variance 1 / (4/3) = 0.75.
  EXPECT_DOUBLE_EQ(iso.z[0][i], 1.75);
  EXPECT_DOUBLE_EQ(iso.variance[0][i], 0.75);
}

TEST(AnalyzeIsotropyTest, IsotropicModelIsIsotropicAndAnisotropicModelIsNot) {
  const int order = 5;
  const PairQuadrature q(kZone, order);
  const GgxBrdf iso_ggx(0.3, 0.3, Rgb(0.5), Rgb(0.1));
  const auto iso = q.ProjectIsotropicBrdf(iso_ggx);
  std::array<Eigen::MatrixXd, 3> tensor;
  for (int ch = 0; ch < 3; ++ch) tensor[ch] = IsotropicLayout(order).Expand(iso[ch]);
  const IsotropyReport isotropic = AnalyzeIsotropy(testing::SyntheticData(tensor, kZone, order, 1e-3));
  EXPECT_TRUE(isotropic.isotropic);
  EXPECT_LT(isotropic.anisotropic_energy_fraction, 1e-5);
  // Pure noise off the blocks: chi-square per degree of freedom about 1 (4 sigma of its spread).
  EXPECT_NEAR(isotropic.chi2_per_dof, 1.0, 4.0 * std::sqrt(2.0 / isotropic.dof));

  const GgxBrdf aniso_ggx(0.15, 0.45, Rgb(0.5), Rgb(0.1));
  const auto aniso = testing::BruteForceTensor(aniso_ggx, kZone, order, 32, 64);
  const IsotropyReport anisotropic = AnalyzeIsotropy(testing::SyntheticData(aniso, kZone, order, 1e-3));
  EXPECT_FALSE(anisotropic.isotropic);
  EXPECT_GT(anisotropic.anisotropic_energy_fraction, kAnisotropyThreshold);
}

TEST(ZonalTensorTest, ProblemsNameTheFault) {
  ZonalTensor data;
  data.theta_min_rad = kZone.theta_min_rad();
  data.theta_max_rad = kZone.theta_max_rad();
  data.order = 1;
  for (int ch = 0; ch < 3; ++ch) {
    data.z[ch] = Eigen::MatrixXd::Zero(4, 4);
    data.variance[ch] = Eigen::MatrixXd::Zero(4, 4);
  }
  EXPECT_EQ(data.Problems(), "");
  data.z[1](2, 3) = NAN;
  EXPECT_NE(data.Problems().find("channel G coefficient (2, 3) is not finite"), std::string::npos);
  data.z[1](2, 3) = 0;
  data.variance[2](0, 0) = -1;
  EXPECT_NE(data.Problems().find("channel B variance (0, 0)"), std::string::npos);
  data.variance[2] = Eigen::MatrixXd::Zero(3, 3);
  EXPECT_NE(data.Problems().find("is not 4 x 4"), std::string::npos);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
