#include "fitting/dbrdf_fit.h"

#include <gtest/gtest.h>

#include "basis/error.h"
#include "brdf/ggx.h"
#include "brdf/lambertian.h"
#include "fitting/fit_common.h"
#include "fitting/fit_error.h"
#include "tests/brdf/brdf_checks.h"
#include "tests/fitting/fit_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

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

// The relative residual of a fitted model against exact data, from the model's own projection
// (DBrdfTensor on the fitter's quadrature), not from the fit's statistics.
double RelativeResidual(const DBrdfParams& model, const ZonalTensor& data) {
  const DBrdfProjection projection =
      ProjectDBrdfTable(Fitter().quadrature(), model.p_h.theta_samples, model.p_h.phi_samples);
  const auto tensor = DBrdfTensor(projection, model, kOrder);
  double diff = 0, norm = 0;
  for (int ch = 0; ch < 3; ++ch) {
    diff += (tensor[ch] - data.z[ch]).squaredNorm();
    norm += data.z[ch].squaredNorm();
  }
  return std::sqrt(diff / norm);
}

class GgxShapedTableTest : public ::testing::TestWithParam<double> {};

TEST_P(GgxShapedTableTest, NarrowAndWideLobesAreRecoveredFromTheirExactProjection) {
  // A GGX-shaped p (alpha 0.02: a 1-2 deg peak, the width of the table's steps; 0.05; 0.2) with a
  // low F0 and a coloured diffuse term. The data lie in the fit's span (p between knots follows
  // the GGX lobe the initial scan finds), so the fit must recover them to its solver's tolerance:
  // measured 1e-11 relative residual, parameters to 1e-9.
  const double alpha = GetParam();
  const DBrdfParams truth =
      testing::GgxShapedDBrdf(alpha, alpha, 91, 1, Rgb(0.6, 0.7, 0.8), 0.05, Rgb(0.05, 0.1, 0.2));
  const ZonalTensor data = DataOf(truth, 0.0);
  const DBrdfFitResult r = Fitter().Fit(data);
  ASSERT_TRUE(r.fitted);
  EXPECT_LT(RelativeResidual(r.params, data), 1e-8);
  EXPECT_NEAR(r.params.f0, truth.f0, 1e-6);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(r.params.c[ch], truth.c[ch], 1e-6 * truth.c[ch]) << ch;
    EXPECT_NEAR(r.params.kd[ch], truth.kd[ch], 1e-6 * truth.kd[ch]) << ch;
  }
  EXPECT_NEAR(r.params.p_h.p[0], truth.p_h.p[0], 1e-6 * truth.p_h.p[0]);
}

INSTANTIATE_TEST_SUITE_P(Alpha, GgxShapedTableTest, ::testing::Values(0.02, 0.05, 0.2),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return "alpha" +
                                  std::to_string(static_cast<int>(std::lround(100 * info.param)));
                         });

TEST(DBrdfFitTest, ATableThatIsNotGgxShapedIsFittedWithinTheModelErrorFloor) {
  // p = (D_0.02 + D_0.2) / 2: a sharp peak on a broad base, which no single GGX lobe (the shape
  // p follows between knots) matches. The fit's best knot values leave 2.1e-4 relative residual
  // (chi2/dof 0.18 against the model-error floor, fit_common.h) with c F0 and kd within 0.2%.
  // The Ceres solve this replaced stopped at 1.4e-3 (chi2/dof 7.8) with c 9.5% high and kd 7%
  // low: Levenberg-Marquardt with bounds on 15 knots stalled ("parameter tolerance reached").
  // Limits: 5e-4 for the residual (the floor's chi2/dof = 1 is about 3e-5 sqrt(dof) = 9e-4), 1%
  // for the colours.
  DBrdfParams truth =
      testing::GgxShapedDBrdf(0.02, 0.02, 91, 1, Rgb(0.6, 0.7, 0.8), 0.05, Rgb(0.05, 0.1, 0.2));
  const DBrdfParams wide =
      testing::GgxShapedDBrdf(0.2, 0.2, 91, 1, Rgb(0.6, 0.7, 0.8), 0.05, Rgb(0.05, 0.1, 0.2));
  for (size_t j = 0; j < truth.p_h.p.size(); ++j)
    truth.p_h.p[j] = 0.5 * (truth.p_h.p[j] + wide.p_h.p[j]);
  truth.p_h.Normalize();
  const ZonalTensor data = DataOf(truth, 0.0);
  const DBrdfFitResult r = Fitter().Fit(data);
  ASSERT_TRUE(r.fitted);
  EXPECT_LT(RelativeResidual(r.params, data), 5e-4);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(r.params.c[ch] * r.params.f0, truth.c[ch] * truth.f0, 0.01 * truth.c[ch] * truth.f0)
        << ch;
    EXPECT_NEAR(r.params.kd[ch], truth.kd[ch], 0.01 * truth.kd[ch]) << ch;
  }
}

TEST(DBrdfFitTest, FitOfAModelItCannotRepresentIsAMinimumOfItsChi2) {
  // A GGX material's exact projection: the D-BRDF cannot represent GGX's 1 / (4 cos cos)
  // geometry (relative residual about 10%), so this checks that the fit is as good as the model
  // allows, not that it is exact: without the smoothness prior, no step in c, kd, F0 (inside its
  // bounds) or in p's linear trend (p times 1 + eps theta / theta_last, in the span of the knots)
  // lowers the chi2, computed here from the model's projection by finite differences.
  const GgxBrdf ggx(0.1, 0.1, Rgb(0.04), Rgb(0.1, 0.2, 0.3));
  const auto iso = Fitter().quadrature().ProjectIsotropicBrdf(ggx);
  std::array<Eigen::MatrixXd, 3> tensor;
  for (int ch = 0; ch < 3; ++ch) tensor[ch] = IsotropicLayout(kOrder).Expand(iso[ch]);
  const ZonalTensor data = testing::SyntheticData(tensor, kZone, kOrder, 0.0);
  DBrdfFitOptions options;
  options.smoothness = 0;
  options.covariance = false;
  const DBrdfFitResult r = DBrdfFitter(kZone, kOrder, options).Fit(data);
  ASSERT_TRUE(r.fitted);
  // The fit's chi2: the isotropic coefficients (+m and -m pooled) weighted by the model-error
  // floor, which for noise-free data is the same for every coefficient of a channel.
  const DBrdfProjection projection = ProjectDBrdfTable(Fitter().quadrature(), 91, 1);
  const IsotropicData y = IsotropicCoefficients(data);
  auto chi2 = [&](const DBrdfParams& params) {
    ZonalTensor model = data;
    model.z = DBrdfTensor(projection, params, kOrder);
    const IsotropicData m = IsotropicCoefficients(model);
    double sum = 0;
    for (int ch = 0; ch < 3; ++ch) sum += (m.z[ch] - y.z[ch]).squaredNorm() / y.z[ch].squaredNorm();
    return sum;
  };
  const double best = chi2(r.params);
  // Steps of 1e-3 (relative, or absolute for values at 0): a stationary point's chi2 changes by
  // O(step^2) = 1e-6 of its value; a missed descent direction lowers it by O(step).
  constexpr double kStep = 1e-3, kTolerance = 1e-9;
  auto expect_no_descent = [&](DBrdfParams trial, const std::string& what) {
    trial.p_h.Normalize();
    EXPECT_GE(chi2(trial), best * (1 - kTolerance)) << what;
  };
  for (int ch = 0; ch < 3; ++ch) {
    for (double sign : {-1.0, 1.0}) {
      DBrdfParams c = r.params, kd = r.params;
      c.c[ch] = std::max(0.0, c.c[ch] * (1 + sign * kStep));
      kd.kd[ch] = kd.kd[ch] > 0 ? kd.kd[ch] * (1 + sign * kStep) : (sign > 0 ? kStep * 0.1 : 0.0);
      expect_no_descent(c, "c channel " + std::to_string(ch));
      expect_no_descent(kd, "kd channel " + std::to_string(ch));
    }
  }
  for (double sign : {-1.0, 1.0}) {
    DBrdfParams f0 = r.params;
    f0.f0 = std::clamp(f0.f0 + sign * kStep * 0.1, options.f0_min, options.f0_max);
    expect_no_descent(f0, "F0");
    DBrdfParams trend = r.params;
    const int last = static_cast<int>(std::ceil(kZone.theta_max_rad() / (M_PI / 180) - 1e-9));
    for (int j = 0; j < 91; ++j) trend.p_h.p[j] *= 1 + sign * kStep * std::min(j, last) / last;
    // Normalize() divides p by its integral; c takes the factor so that c p is unchanged there.
    HalfVectorTable scaled = trend.p_h;
    scaled.Normalize();
    trend.c = trend.c * (trend.p_h.p[0] / scaled.p[0]);
    expect_no_descent(trend, "p's linear trend");
  }
}

TEST(DBrdfFitTest, NarrowLobesAreFittedWithoutTheQuadraturesError) {
  // Order 4 on the full preset's zone (9.7-56.5 deg), as the demo: the data are the projection of
  // a GGX-shaped D-BRDF (alpha 0.05, a 3 deg lobe) by a 200-node reference rule, i.e. what an
  // exact capture measures, not the fitter's own quadrature. With the quadrature's default 40
  // nodes the fitter's projection of the lobe was off by 0.1-13% per table node (13% at theta_h =
  // 0), which the fit absorbed into its parameters: kd 8% and c F0 3.9% off (alpha 0.03: 44% and
  // 19%). With two nodes per degree of the zone (94), measured kd 0.05%, c F0 0.09%, relative
  // residual 3.5e-5. Limits 1% and 2e-4: the 94-node rule's remaining error (5e-4 on the
  // theta_h = 0 node, 1e-4 elsewhere) with margin.
  const Zone zone = Zone::FromDegrees(9.7, 56.5);
  const int order = 4;
  const DBrdfParams truth =
      testing::GgxShapedDBrdf(0.05, 0.05, 91, 1, Rgb(0.6, 0.7, 0.8), 0.5, Rgb(0.1, 0.2, 0.3));
  PairQuadratureOptions reference_options;
  reference_options.theta_nodes = 200;
  const PairQuadrature reference(zone, order, reference_options);
  const auto tensor = DBrdfTensor(ProjectDBrdfTable(reference, 91, 1), truth, order);
  const ZonalTensor data = testing::SyntheticData(tensor, zone, order, 0.0);
  const DBrdfFitResult r = FitDBrdf(data);
  ASSERT_TRUE(r.fitted);
  const auto fitted = DBrdfTensor(ProjectDBrdfTable(reference, 91, 1), r.params, order);
  double diff = 0, norm = 0;
  for (int ch = 0; ch < 3; ++ch) {
    diff += (fitted[ch] - tensor[ch]).squaredNorm();
    norm += tensor[ch].squaredNorm();
  }
  EXPECT_LT(std::sqrt(diff / norm), 2e-4);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(r.params.kd[ch], truth.kd[ch], 0.01 * truth.kd[ch]) << ch;
    EXPECT_NEAR(r.params.c[ch] * r.params.f0, truth.c[ch] * truth.f0, 0.01 * truth.c[ch] * truth.f0)
        << ch;
  }
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
  // section 3.4.2): chi-square test of the sampler against its Pdf. Its sampling density is
  // piecewise constant between the table's theta_h nodes (brdf/dbrdf.h; the table is isotropic,
  // so uniform in phi_h): the normalization is integrated over half vectors on those cells,
  // to ~1e-9, which 1e-6 bounds.
  const DBrdfFitResult r = Fitter().Fit(DataOf(GgxShapedDBrdf(0.2, 0.2, 91, 1), 0.01, 5));
  ASSERT_TRUE(r.fitted);
  const DBrdf model(r.params);
  ASSERT_EQ(model.table().phi_samples, 1);
  testing::SamplingCheckOptions options = testing::PiecewiseDensityCubature();
  for (int j = 0; j < model.table().theta_samples; ++j) {
    options.half_vector_theta_edges.push_back(j * model.table().ThetaStep());
  }
  EXPECT_SAMPLING_MATCHES_PDF(model, Normalize(Vec3{0.6, 0.2, 0.5}), 17, 1e-6, options);
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

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
