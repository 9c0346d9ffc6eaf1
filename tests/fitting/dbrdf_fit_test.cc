#include "fitting/dbrdf_fit.h"

#include <gtest/gtest.h>

#include "basis/error.h"

#include "brdf/ggx.h"
#include "brdf/lambertian.h"
#include "fitting/fit_error.h"
#include "tests/brdf/brdf_checks.h"
#include "tests/fitting/fit_test_util.h"

namespace zbrdf {
namespace {

const Zone kZone = Zone::FromDegrees(11.3, 54.9);  // the thesis rig at the fast preset
constexpr int kOrder = 8;

DBrdfParams GgxShapedDBrdf(double alpha_x, double alpha_y, int theta_samples, int phi_samples) {
  return testing::GgxShapedDBrdf(alpha_x, alpha_y, theta_samples, phi_samples, Rgb(0.6, 0.7, 0.8), 0.5, Rgb(0.1, 0.2, 0.3));
}

// One fitter (quadrature and 1-D projection) for the whole binary.
const DBrdfFitter& Fitter() {
  static const DBrdfFitter fitter(kZone, kOrder);
  return fitter;
}

ZonalTensor DataOf(const DBrdfParams& params, double relative_sigma, uint64_t seed = 7) {
  const DBrdfProjection projection = ProjectDBrdfTable(Fitter().quadrature(), params.p_h.theta_samples,
                                                       params.p_h.phi_samples);
  return testing::SyntheticData(DBrdfTensor(projection, params, kOrder), kZone, kOrder, relative_sigma, seed);
}

void ExpectFinite(const DBrdfFitResult& r) {
  EXPECT_TRUE(r.params.c.IsFinite() && r.params.kd.IsFinite() && std::isfinite(r.params.f0));
  for (double v : r.params.p_h.p) EXPECT_TRUE(std::isfinite(v) && v >= 0);
  EXPECT_NO_THROW(DBrdf{r.params});  // a valid, normalized model
}

TEST(DBrdfFitTest, RecoversExactDBrdfData) {
  const DBrdfParams truth = GgxShapedDBrdf(0.25, 0.25, 91, 1);
  const DBrdfFitResult r = Fitter().Fit(DataOf(truth, 0.0));
  ASSERT_TRUE(r.fitted);
  EXPECT_TRUE(r.isotropic_table);
  ExpectFinite(r);
  // The data lie in the model's span (p between knots follows the GGX prior shape, which the
  // initial scan finds exactly): recovery to the solver's tolerance.
  EXPECT_NEAR(r.params.f0, truth.f0, 1e-6);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(r.params.c[ch], truth.c[ch], 1e-6 * truth.c[ch]);
    EXPECT_NEAR(r.params.kd[ch], truth.kd[ch], 1e-6);
  }
  for (size_t j = 0; j < truth.p_h.p.size(); ++j) {
    EXPECT_NEAR(r.params.p_h.p[j], truth.p_h.p[j], 1e-6 * truth.p_h.p[0]) << j;
  }
  EXPECT_LT(r.statistics.relative_residual, 1e-8);
  // Exact data leave no misfit beyond their noise: the smoothness prior is not applied.
  EXPECT_EQ(r.smoothness_weight, 0.0);
}

TEST(DBrdfFitTest, SmoothnessPriorActsOnlyOnMisfitBeyondTheNoiseAndCostsLittle) {
  // Coefficient errors of 0.3% of the RMS coefficient that the variances do not record (they say
  // 0.02%), as in the simulated captures (15x their noise). Such white errors barely move kd
  // (measured: 0.4% without the prior, 0.25% with it); the failure the prior is for, p's tail
  // collapsing under correlated capture errors, is fit_session_test.cc's D-BRDF ground truth
  // (kd 8-15% high without it). Here: the prior is applied, keeps kd within 2%, and costs at
  // most 10% of the data's chi2 (dbrdf_fit.h, step 5). Exact data do not get it
  // (RecoversExactDBrdfData).
  const DBrdfParams truth = GgxShapedDBrdf(0.2, 0.2, 91, 1);
  ZonalTensor data = DataOf(truth, 0.003, 5);
  for (int ch = 0; ch < 3; ++ch) data.variance[ch] *= (0.0002 / 0.003) * (0.0002 / 0.003);
  DBrdfFitOptions free_options;
  free_options.smoothness = 0;
  const DBrdfFitResult unregularized = DBrdfFitter(kZone, kOrder, free_options).Fit(data);
  const DBrdfFitResult r = Fitter().Fit(data);
  ASSERT_TRUE(r.fitted && unregularized.fitted);
  EXPECT_EQ(unregularized.smoothness_weight, 0.0);
  EXPECT_GT(r.smoothness_weight, 0.0);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(r.params.kd[ch], truth.kd[ch], 0.02 * truth.kd[ch]) << ch;
  EXPECT_LE(r.statistics.chi2, 1.1 * unregularized.statistics.chi2 * (1 + 1e-9));
}

TEST(DBrdfFitTest, NoisyDataGiveConsistentUncertainties) {
  const DBrdfParams truth = GgxShapedDBrdf(0.2, 0.2, 91, 1);
  // White noise of 1% of the RMS coefficient on every coefficient, its variance recorded.
  const DBrdfFitResult r = Fitter().Fit(DataOf(truth, 0.01, 21));
  ASSERT_TRUE(r.fitted);
  ExpectFinite(r);
  // chi2/dof of a correct model on Gaussian noise: 1 +- sqrt(2 / dof) (~0.05 here); 4 sigma.
  EXPECT_NEAR(r.statistics.chi2_per_dof, 1.0, 4 * std::sqrt(2.0 / r.statistics.residuals));
  ASSERT_TRUE(r.uncertainty.available);
  // Estimates within 4 of their reported standard deviations.
  EXPECT_NEAR(r.params.f0, truth.f0, 4 * r.uncertainty.f0);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(r.params.c[ch], truth.c[ch], 4 * r.uncertainty.c[ch]);
    EXPECT_NEAR(r.params.kd[ch], truth.kd[ch], 4 * r.uncertainty.kd[ch]);
    EXPECT_GT(r.uncertainty.kd[ch], 0);
  }
  // The fitted BRDF matches the truth where the data are (noise-limited).
  const BrdfComparison c = CompareBrdfs(DBrdf(r.params), DBrdf(truth), kZone);
  EXPECT_LT(c.in_zone, 0.03);
}

TEST(DBrdfFitTest, AnisotropicDataGetATwoDimensionalTable) {
  const DBrdfParams truth = GgxShapedDBrdf(0.15, 0.4, 46, 8);
  const DBrdfFitResult r = Fitter().Fit(DataOf(truth, 1e-3));
  ASSERT_TRUE(r.fitted);
  EXPECT_FALSE(r.isotropy.isotropic);
  EXPECT_FALSE(r.isotropic_table);
  EXPECT_EQ(r.params.p_h.phi_samples, 8);
  ExpectFinite(r);
  const BrdfComparison c = CompareBrdfs(DBrdf(r.params), DBrdf(truth), kZone);
  // The knots are coarser than the true table (2-6 deg) and the tail is an isotropic GGX shape
  // scaled per phi: a few percent in the zone. (F0, weakly determined by the zone, trades with
  // that approximation and is not checked.)
  EXPECT_LT(c.in_zone, 0.05);
  // The lobe is wider along y (alpha_y > alpha_x): beyond the peak p is larger at phi_h = 90
  // deg than at 0, as in the truth.
  const HalfVectorTable& p = r.params.p_h;
  for (int j : {5, 10}) {  // 10 and 20 deg (2 deg nodes)
    EXPECT_GT(truth.p_h.At(j, 2), 1.5 * truth.p_h.At(j, 0));
    EXPECT_GT(p.At(j, 2), 1.5 * p.At(j, 0)) << j;
  }
}

TEST(DBrdfFitTest, AllZeroDataReportNothingToFit) {
  const DBrdfParams truth = GgxShapedDBrdf(0.2, 0.2, 91, 1);
  ZonalTensor data = DataOf(truth, 0.0);
  for (int ch = 0; ch < 3; ++ch) {
    data.z[ch].setZero();
    data.variance[ch].setConstant(1e-6);
  }
  const DBrdfFitResult r = Fitter().Fit(data);
  EXPECT_FALSE(r.fitted);
  ExpectFinite(r);
  EXPECT_EQ(r.params.c, Rgb(0.0));
  EXPECT_EQ(r.params.kd, Rgb(0.0));
  ASSERT_FALSE(r.conditions.empty());
  EXPECT_NE(r.conditions[0].find("all zero"), std::string::npos);
}

TEST(DBrdfFitTest, NonFiniteCoefficientsAreDroppedAndReported) {
  const DBrdfParams truth = GgxShapedDBrdf(0.3, 0.3, 91, 1);
  ZonalTensor data = DataOf(truth, 1e-3);
  data.z[1](3, 5) = NAN;
  data.variance[2](0, 0) = INFINITY;
  const DBrdfFitResult r = FitDBrdf(data);
  ASSERT_TRUE(r.fitted);
  ExpectFinite(r);
  bool reported = false;
  for (const std::string& c : r.conditions) reported = reported || c.find("not finite") != std::string::npos;
  EXPECT_TRUE(reported);
  EXPECT_NEAR(r.params.f0, truth.f0, 0.02);
}

TEST(DBrdfFitTest, PureDiffuseDataGiveTheAlbedoAndNoSpecularLobe) {
  const LambertianBrdf lambert(Rgb(0.5, 0.3, 0.1));
  const auto iso = Fitter().quadrature().ProjectIsotropicBrdf(lambert);
  std::array<Eigen::MatrixXd, 3> tensor;
  for (int ch = 0; ch < 3; ++ch) tensor[ch] = IsotropicLayout(kOrder).Expand(iso[ch]);
  const DBrdfFitResult r = Fitter().Fit(testing::SyntheticData(tensor, kZone, kOrder, 1e-3));
  ASSERT_TRUE(r.fitted);
  ExpectFinite(r);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(r.params.kd[ch], lambert.albedo()[ch], 0.01 * lambert.albedo()[ch]);
  // Whatever specular part remains reflects a tiny fraction of what the diffuse part does.
  EXPECT_LT(r.params.c.Max() * r.params.f0, 0.01 * lambert.albedo().Max());
}

TEST(DBrdfFitTest, MirrorLikeLobesAreHeldAtTheTableResolutionAndReported) {
  DBrdfParams truth = GgxShapedDBrdf(0.008, 0.008, 91, 1);  // narrower than a 1 deg table step
  truth.kd = Rgb(0.0);
  const DBrdfFitResult r = Fitter().Fit(DataOf(truth, 1e-3));
  ASSERT_TRUE(r.fitted);
  ExpectFinite(r);
  bool reported = false;
  for (const std::string& c : r.conditions) reported = reported || c.find("narrow") != std::string::npos;
  EXPECT_TRUE(reported) << r.ToJson().dump();
}

TEST(DBrdfFitTest, FittedModelSamplesItsHalfVectorDistribution) {
  // The fitted model draws h from its own table by 2-D CDF inversion and reflects w_o (thesis
  // section 3.4.2): chi-square test of the sampler against its Pdf.
  const DBrdfFitResult r = Fitter().Fit(DataOf(GgxShapedDBrdf(0.2, 0.2, 91, 1), 0.01, 5));
  ASSERT_TRUE(r.fitted);
  const DBrdf model(r.params);
  EXPECT_SAMPLING_MATCHES_PDF(model, Normalize(Vec3{0.6, 0.2, 0.5}), 17, 2e-3);
}

TEST(DBrdfFitTest, RejectsDataOfAnotherZoneOrOrder) {
  ZonalTensor data = DataOf(GgxShapedDBrdf(0.2, 0.2, 91, 1), 0.0);
  data.theta_max_rad += 0.01;
  EXPECT_THROW(Fitter().Fit(data), InputError);
  DBrdfFitOptions bad;
  bad.f0_min = 0.5;
  bad.f0_max = 0.2;
  EXPECT_THROW(DBrdfFitter(kZone, 2, bad), InputError);
}

}  // namespace
}  // namespace zbrdf
