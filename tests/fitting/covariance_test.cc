#include "fitting/covariance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Eigen/Dense>
#include <ceres/ceres.h>

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// Residual (a + b x - y) / sigma of a straight-line fit; `b` may be the same block as `a`'s twin.
struct Line {
  double x, y, sigma;
  template <typename T>
  bool operator()(const T* a, const T* b, T* residual) const {
    residual[0] = (a[0] + b[0] * x - y) / sigma;
    return true;
  }
};

// A linear least-squares problem: the covariance of (a, b) is (J^T J)^-1 exactly, J the
// whitened design matrix, so the standard deviations have a closed form to compare with.
TEST(ParameterStandardDeviations, MatchTheLinearLeastSquaresClosedFormAndInflate) {
  const std::vector<double> xs = {-1.0, -0.25, 0.5, 1.5, 2.0};
  const double sigma = 0.1;
  double a = 0.3, b = -0.7;
  ceres::Problem problem;
  Eigen::MatrixXd j(xs.size(), 2);
  for (size_t i = 0; i < xs.size(); ++i) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Line, 1, 1, 1>(
                                 new Line{xs[i], 0.3 - 0.7 * xs[i], sigma}),
                             nullptr, &a, &b);
    j(i, 0) = 1 / sigma;
    j(i, 1) = xs[i] / sigma;
  }
  const Eigen::Matrix2d covariance = (j.transpose() * j).inverse();
  const auto sd = ParameterStandardDeviations(problem, {{&a, 1}, {&b, 1}}, 0.5);
  ASSERT_TRUE(sd.has_value());
  ASSERT_EQ(sd->size(), 2u);
  // Dense SVD of a 5 x 2 well-conditioned Jacobian: rounding only.
  EXPECT_NEAR((*sd)[0][0], std::sqrt(covariance(0, 0)), 1e-12);
  EXPECT_NEAR((*sd)[1][0], std::sqrt(covariance(1, 1)), 1e-12);
  // chi2/dof = 4: the deviations double; below 1 they are never narrowed (0.5 above).
  const auto inflated = ParameterStandardDeviations(problem, {{&a, 1}, {&b, 1}}, 4.0);
  ASSERT_TRUE(inflated.has_value());
  EXPECT_NEAR((*inflated)[0][0], 2 * std::sqrt(covariance(0, 0)), 1e-12);
  EXPECT_NEAR((*inflated)[1][0], 2 * std::sqrt(covariance(1, 1)), 1e-12);
}

TEST(ParameterStandardDeviations, ARankDeficientProblemGetsThePseudoInverse) {
  // a and b enter only as their sum: J = (1 / sigma) [1 1] in each of 3 rows, so J^T J has the
  // single eigenvalue 6 / sigma^2 along (1, 1) / sqrt(2) and 0 across it. Dropping the null
  // direction leaves the diagonal sigma^2 / 12 for both.
  const double sigma = 0.1;
  double a = 0.2, b = 0.1;
  ceres::Problem problem;
  for (double y : {0.25, 0.35, 0.3}) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<Line, 1, 1, 1>(new Line{1.0, y, sigma}), nullptr, &a, &b);
  }
  const auto sd = ParameterStandardDeviations(problem, {{&a, 1}, {&b, 1}}, 1.0);
  ASSERT_TRUE(sd.has_value());
  EXPECT_NEAR((*sd)[0][0], sigma / std::sqrt(12.0), 1e-12);
  EXPECT_NEAR((*sd)[1][0], sigma / std::sqrt(12.0), 1e-12);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
