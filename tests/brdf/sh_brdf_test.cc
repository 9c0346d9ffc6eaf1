#include "brdf/sh_brdf.h"

#include <gtest/gtest.h>

#include "basis/spherical_harmonics.h"
#include "basis/zone.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

ShBrdfData Data(TargetKind target, int order) {
  ShBrdfData data;
  data.theta_min_rad = DegToRad(9);
  data.theta_max_rad = DegToRad(57);
  data.target = target;
  data.order = order;
  data.exitant_theta = 10;
  data.exitant_phi = 10;
  const int n = data.size();
  for (int ch = 0; ch < 3; ++ch) data.coefficients[ch] = Eigen::MatrixXd::Zero(n, n);
  return data;
}

TEST(ShBrdfTest, EvaluatesTheTensorFormDividedByCosine) {
  // f^ = a Y_00(w_i) Y_00(w_r) + b Y_10(w_i) Y_00(w_r) = (a + b sqrt(3) cos(theta_i)) / (4 pi):
  // f_r = f^ / cos(theta_i).
  ShBrdfData data = Data(TargetKind::kSh, 1);
  const double a = 0.2, b = 0.6;
  data.coefficients[0](ShIndex(0, 0), ShIndex(0, 0)) = a;
  data.coefficients[0](ShIndex(1, 0), ShIndex(0, 0)) = b;
  data.coefficients[2] = 2 * data.coefficients[0];
  const ShBrdf brdf(data);
  for (double theta_i : {0.1, 0.7, 1.3}) {
    const Vec3 w_i = SphericalDirection(theta_i, 0.4), w_o = SphericalDirection(0.5, 2.0);
    const double f_hat = (a + b * std::sqrt(3.0) * std::cos(theta_i)) / (4 * M_PI);
    const Rgb f = brdf.Eval(w_i, w_o);
    EXPECT_NEAR(f.r, f_hat / std::cos(theta_i), 1e-14);
    EXPECT_EQ(f.g, 0.0);
    EXPECT_NEAR(f.b, 2 * f_hat / std::cos(theta_i), 1e-14);
    EXPECT_NEAR(brdf.CosineWeighted(w_i, w_o).r, f_hat, 1e-15);
  }
  EXPECT_EQ(brdf.Eval(Vec3{0, 0.6, -0.8}, Vec3{0, 0, 1}), Rgb());
  EXPECT_EQ(brdf.negative_evaluations(), 0u);
  EXPECT_EQ(brdf.evaluations(), 3u);
}

TEST(ShBrdfTest, ClampsNegativeValuesAndCountsThem) {
  // f^ = Y_11(w_i) Y_00(w_r): with the Condon-Shortley phase Y_11 = -sqrt(3 / 4 pi) x, negative
  // for x > 0 and positive for x < 0.
  ShBrdfData data = Data(TargetKind::kSh, 1);
  for (int ch = 0; ch < 3; ++ch) data.coefficients[ch](ShIndex(1, 1), ShIndex(0, 0)) = 1.0;
  const ShBrdf brdf(data);
  const Vec3 w_o{0, 0, 1};
  const Rgb positive = brdf.Eval(Normalize(Vec3{-0.5, 0, 0.8}), w_o);
  EXPECT_GT(positive.r, 0);
  EXPECT_EQ(brdf.Eval(Normalize(Vec3{0.5, 0, 0.8}), w_o), Rgb());
  EXPECT_LT(brdf.CosineWeighted(Normalize(Vec3{0.5, 0, 0.8}), w_o).r, 0);
  EXPECT_EQ(brdf.evaluations(), 2u);
  EXPECT_EQ(brdf.negative_evaluations(), 1u);
  brdf.ResetCounters();
  EXPECT_EQ(brdf.evaluations(), 0u);
}

TEST(ShBrdfTest, BatchAndPerExitantFormsAgreeWithEval) {
  ShBrdfData data = Data(TargetKind::kShOdd, 4);
  const int n = data.size();
  for (int ch = 0; ch < 3; ++ch) {
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) data.coefficients[ch](i, j) = std::sin(1.0 + i + 2.0 * j + ch);
    }
  }
  const ShBrdf brdf(data);
  std::vector<Vec3> wi, wo;
  for (int k = 0; k < 20; ++k) {
    wi.push_back(SphericalDirection(0.05 + 0.07 * k, 0.3 * k));
    wo.push_back(SphericalDirection(0.4 + 0.02 * (k / 5), 1.0 + (k / 5)));
  }
  std::vector<Rgb> f(wi.size());
  brdf.EvalBatch(wi, wo, f);
  for (size_t k = 0; k < wi.size(); ++k) {
    const Rgb e = brdf.Eval(wi[k], wo[k]);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(f[k][ch], e[ch], 1e-12 * (1 + std::abs(e[ch])));
  }
  // The per-exitant table at a cell centre is y(w_r): f^ = sum_a y_a T_a(w_i).
  const Vec3 centre = data.ExitantDirection(4, 7);
  const TargetBasis basis(TargetKind::kShOdd, 4);
  Eigen::VectorXd t(n);
  basis.Eval(wi[3], t.data());
  double from_table = 0;
  for (int a = 0; a < n; ++a) from_table += brdf.data().exitant[0][(4 * 10 + 7) * n + a] * t[a];
  // The table is float: 6e-8 relative per coefficient.
  EXPECT_NEAR(from_table, brdf.CosineWeighted(wi[3], centre).r, 1e-5);
}

TEST(ShBrdfTest, SpecNamesTheSourceFile) {
  EXPECT_EQ(ShBrdf(Data(TargetKind::kSh, 1), "a/b.exr").Spec(), "file:a/b.exr");
  EXPECT_NE(ShBrdf(Data(TargetKind::kHsh, 2)).Spec().find("target=hsh"), std::string::npos);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
