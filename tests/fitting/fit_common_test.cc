#include "fitting/fit_common.h"

#include <random>

#include <gtest/gtest.h>

#include "brdf/ggx.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// Reference NNLS: every subset of columns as the passive set, the best feasible solution.
Eigen::VectorXd EnumerateNnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b) {
  const int n = static_cast<int>(a.cols());
  Eigen::VectorXd best = Eigen::VectorXd::Zero(n);
  double best_cost = (a * best - b).squaredNorm();
  for (int mask = 1; mask < (1 << n); ++mask) {
    std::vector<int> cols;
    for (int j = 0; j < n; ++j) {
      if (mask & (1 << j)) cols.push_back(j);
    }
    Eigen::MatrixXd sub(a.rows(), cols.size());
    for (size_t k = 0; k < cols.size(); ++k) sub.col(k) = a.col(cols[k]);
    const Eigen::VectorXd x = sub.colPivHouseholderQr().solve(b);
    if (x.minCoeff() < 0) continue;
    Eigen::VectorXd full = Eigen::VectorXd::Zero(n);
    for (size_t k = 0; k < cols.size(); ++k) full[cols[k]] = x[k];
    const double cost = (a * full - b).squaredNorm();
    if (cost < best_cost) {
      best_cost = cost;
      best = full;
    }
  }
  return best;
}

TEST(NonNegativeLeastSquaresTest, MatchesExhaustiveSearch) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 1 + trial % 4;
    Eigen::MatrixXd a(12, n);
    Eigen::VectorXd b(12);
    for (int i = 0; i < a.size(); ++i) a.data()[i] = normal(rng);
    for (int i = 0; i < b.size(); ++i) b[i] = normal(rng);
    const Eigen::VectorXd x = NonNegativeLeastSquares(a, b);
    const Eigen::VectorXd reference = EnumerateNnls(a, b);
    EXPECT_GE(x.minCoeff(), 0.0);
    // Same optimum (a strictly convex problem for full-rank a): to solver precision.
    EXPECT_NEAR((a * x - b).squaredNorm(), (a * reference - b).squaredNorm(), 1e-10) << trial;
    EXPECT_LT((x - reference).norm(), 1e-8) << trial;
  }
}

TEST(MinimizeScalarTest, FindsTheGlobalMinimumAfterTheScan) {
  // Two local minima; the deeper one at 2.5.
  const auto f = [](double x) { return std::min((x + 1) * (x + 1) + 0.5, 3 * (x - 2.5) * (x - 2.5)); };
  EXPECT_NEAR(MinimizeScalar(f, -3.0, 4.0), 2.5, 1e-6);
  EXPECT_NEAR(MinimizeScalar([](double x) { return std::cos(x); }, 0.0, 6.0), M_PI, 1e-6);
}

TEST(GgxDTest, MatchesTheBrdfClassAndIsNormalized) {
  const GgxBrdf ggx(0.2, 0.2, Rgb(0.5), Rgb(0.0));
  for (double theta : {0.0, 0.1, 0.5, 1.2}) {
    EXPECT_NEAR(GgxD(0.2, theta), ggx.D(SphericalDirection(theta, 0.3)), 1e-12 * ggx.D(SphericalDirection(theta, 0.3)));
  }
  // integral D cos dw = 1: Gauss-Legendre in theta on pieces resolving the peak.
  double integral = 0;
  const double pieces[] = {0, 0.05, 0.2, 0.6, M_PI / 2};
  for (int p = 0; p < 4; ++p) {
    const int n = 200;
    for (int i = 0; i < n; ++i) {
      const double t = pieces[p] + (pieces[p + 1] - pieces[p]) * (i + 0.5) / n;
      integral += GgxD(0.2, t) * std::cos(t) * std::sin(t) * 2 * M_PI * (pieces[p + 1] - pieces[p]) / n;
    }
  }
  EXPECT_NEAR(integral, 1.0, 1e-4);  // midpoint rule, 800 cells
}

TEST(FitWeightsTest, ReportsDegenerateData) {
  std::array<Eigen::VectorXd, 3> y, var;
  for (int ch = 0; ch < 3; ++ch) {
    y[ch] = Eigen::VectorXd::Zero(10);
    var[ch] = Eigen::VectorXd::Ones(10);
  }
  FitWeights w = MakeFitWeights(y, var);
  EXPECT_FALSE(w.any_signal);
  ASSERT_FALSE(w.conditions.empty());
  EXPECT_NE(w.conditions.back().find("all zero"), std::string::npos);

  for (int ch = 0; ch < 3; ++ch) {
    y[ch] = Eigen::VectorXd::LinSpaced(10, 1.0, 2.0);
    var[ch] = Eigen::VectorXd::Zero(10);
  }
  y[1][3] = NAN;
  w = MakeFitWeights(y, var);
  EXPECT_TRUE(w.any_signal);
  EXPECT_EQ(w.used, 29);
  EXPECT_EQ(w.weight[1][3], 0.0);
  ASSERT_EQ(w.conditions.size(), 2u);
  EXPECT_NE(w.conditions[0].find("1 of 30 coefficients are not finite"), std::string::npos);
  EXPECT_NE(w.conditions[1].find("no variances"), std::string::npos);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
