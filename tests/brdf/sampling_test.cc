#include "brdf/sampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "basis/error.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Rng;

TEST(Distribution1DTest, StratifiedSamplesFillCellsInProportionToWeights) {
  const std::vector<double> weights = {1.0, 0.0, 3.0, 0.5, 0.0, 2.5};
  const Distribution1D dist(weights);
  const double sum = 7.0;
  const int n = 70000;  // u = (k + 0.5) / n: each cell gets weight/sum * n points, +-1
  std::vector<int> counts(weights.size(), 0);
  for (int k = 0; k < n; ++k) {
    double pdf = 0;
    int cell = -1;
    const double x = dist.Sample((k + 0.5) / n, &pdf, &cell);
    ASSERT_GE(x, 0.0);
    ASSERT_LT(x, 1.0);
    ASSERT_EQ(cell, static_cast<int>(x * weights.size()));
    ASSERT_DOUBLE_EQ(pdf, weights[cell] * weights.size() / sum);
    ASSERT_DOUBLE_EQ(dist.Pdf(x), pdf);
    ++counts[cell];
  }
  for (size_t j = 0; j < weights.size(); ++j) {
    EXPECT_NEAR(counts[j], weights[j] / sum * n, 1.0) << "cell " << j;
    EXPECT_DOUBLE_EQ(dist.Pmf(static_cast<int>(j)), weights[j] / sum);
  }
  EXPECT_DOUBLE_EQ(dist.WeightSum(), sum);
}

TEST(Distribution1DTest, ContinuousSampleIsUniformWithinACell) {
  // One cell of weight 1 among zeros: x must be uniform on [2/4, 3/4), i.e. affine in u.
  const std::vector<double> weights = {0.0, 0.0, 1.0, 0.0};
  const Distribution1D dist(weights);
  for (double u : {0.0, 0.25, 0.5, 0.75}) {
    EXPECT_NEAR(dist.Sample(u), 0.5 + 0.25 * u, 1e-15) << "u=" << u;
  }
}

TEST(Distribution1DTest, EdgeUniformsNeverReachZeroWeightCells) {
  const std::vector<double> weights = {0.0, 0.1, 0.2, 0.3, 0.0, 0.0};
  const Distribution1D dist(weights);
  const double almost_one = std::nextafter(1.0, 0.0);
  int cell = -1;
  dist.Sample(0.0, nullptr, &cell);
  EXPECT_EQ(cell, 1);
  dist.Sample(almost_one, nullptr, &cell);
  EXPECT_EQ(cell, 3);
  double remapped = -1;
  EXPECT_EQ(dist.SampleDiscrete(almost_one, nullptr, &remapped), 3);
  EXPECT_LT(remapped, 1.0);
  EXPECT_EQ(dist.Pdf(1.0), 0.0);
  EXPECT_EQ(dist.Pdf(-0.1), 0.0);
}

TEST(Distribution1DTest, CellsAreThoseOfABinarySearchOfTheCdf) {
  // A peaked distribution like the proxy sampler's lobes (128 cells, runs of zeros, weights
  // over 12 decades) and uniforms on both sides of every cdf entry and of every guide boundary
  // g / n, where the cell search starts: the cell must be the one a binary search of the cdf
  // finds (the cdf as documented: running sums over the total, 1 after the last positive
  // weight), and always one of positive weight.
  const int n = 128;
  std::vector<double> weights(n, 0.0);
  for (int k = 0; k < n; ++k) {
    if (k % 17 == 3 || (k > 40 && k < 52)) continue;
    weights[k] = std::exp(-0.5 * (k - 20) * (k - 20) / 9.0) + 1e-12 * k;
  }
  weights[n - 1] = weights[n - 2] = 0.0;
  const Distribution1D dist(weights);
  std::vector<double> cdf(n + 1, 0.0);
  for (int k = 0; k < n; ++k) cdf[k + 1] = cdf[k] + weights[k];
  const double sum = cdf[n];
  for (int k = 1; k <= n; ++k) cdf[k] = k >= n - 2 ? 1.0 : cdf[k] / sum;
  std::vector<double> us;
  for (int k = 0; k <= n; ++k) {
    for (double edge : {cdf[k], static_cast<double>(k) / n}) {
      us.push_back(edge);
      us.push_back(std::nextafter(edge, 0.0));
      us.push_back(std::nextafter(edge, 2.0));
    }
  }
  Rng rng(7);
  for (int i = 0; i < 10000; ++i) us.push_back(rng.Uniform());
  for (double u : us) {
    if (!(u >= 0 && u < 1)) continue;
    const int expected = std::clamp(
        static_cast<int>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()) - 1, 0, n - 1);
    const int cell = dist.SampleDiscrete(u);
    ASSERT_EQ(cell, expected) << "u=" << u;
    ASSERT_GT(weights[cell], 0.0) << "u=" << u;
  }
}

TEST(Distribution1DTest, DiscreteRemappedUniformIsUniform) {
  const std::vector<double> weights = {2.0, 1.0};
  const Distribution1D dist(weights);
  // u in the first 2/3 maps to cell 0 with u_remapped = u / (2/3).
  double pmf = 0, remapped = 0;
  EXPECT_EQ(dist.SampleDiscrete(0.5, &pmf, &remapped), 0);
  EXPECT_DOUBLE_EQ(pmf, 2.0 / 3.0);
  EXPECT_NEAR(remapped, 0.75, 1e-15);
  EXPECT_EQ(dist.SampleDiscrete(5.0 / 6.0, &pmf, &remapped), 1);
  EXPECT_NEAR(remapped, 0.5, 1e-15);
}

TEST(Distribution1DTest, RejectsInvalidWeights) {
  EXPECT_THROW(Distribution1D(std::vector<double>{}), InputError);
  EXPECT_THROW(Distribution1D(std::vector<double>{1.0, -0.5}), InputError);
  EXPECT_THROW(Distribution1D(std::vector<double>{0.0, 0.0}), InputError);
  EXPECT_THROW(Distribution1D(std::vector<double>{1.0, std::nan("")}), InputError);
  EXPECT_THROW(Distribution1D(std::vector<double>{std::numeric_limits<double>::infinity()}),
               InputError);
}

TEST(Distribution2DTest, StratifiedSamplesMatchCellWeights) {
  const int nx = 5, ny = 4;
  std::vector<double> weights(nx * ny);
  Rng rng(7);
  double sum = 0;
  for (double& w : weights) {
    w = rng.Uniform() < 0.2 ? 0.0 : rng.Uniform();
    sum += w;
  }
  weights[2 * nx + 0] = weights[2 * nx + 1] = weights[2 * nx + 2] = weights[2 * nx + 3] =
      weights[2 * nx + 4] = 0.0;  // an all-zero row
  sum = 0;
  for (double w : weights) sum += w;
  const Distribution2D dist(weights, nx, ny);
  const int n = 512;
  std::vector<int> counts(nx * ny, 0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      double pdf = 0;
      const auto [x, y] = dist.Sample((i + 0.5) / n, (j + 0.5) / n, &pdf);
      const int ix = static_cast<int>(x * nx), iy = static_cast<int>(y * ny);
      ASSERT_GT(weights[iy * nx + ix], 0.0);
      ASSERT_NEAR(pdf, weights[iy * nx + ix] * nx * ny / sum, 1e-12);
      ASSERT_NEAR(dist.Pdf(x, y), pdf, 1e-12);
      ++counts[iy * nx + ix];
    }
  }
  for (int k = 0; k < nx * ny; ++k) {
    // Row and column boundaries each shift a cell's count by at most one grid line: the
    // fraction is within 2/n of the weight's share.
    EXPECT_NEAR(static_cast<double>(counts[k]) / (n * n), weights[k] / sum, 2.0 / n)
        << "cell " << k;
    EXPECT_NEAR(dist.CellProbability(k % nx, k / nx), weights[k] / sum, 1e-15);
  }
}

TEST(Distribution2DTest, RejectsBadShapes) {
  const std::vector<double> weights(6, 1.0);
  EXPECT_THROW(Distribution2D(weights, 4, 2), InputError);
  EXPECT_THROW(Distribution2D(weights, 0, 6), InputError);
  EXPECT_THROW(Distribution2D(std::vector<double>(6, 0.0), 3, 2), InputError);
}

TEST(HalfVectorTest, UpperHalfVectorBisectsAndFlipsIntoTheUpperHemisphere) {
  const Vec3 w_i = Normalize(Vec3{0.3, -0.2, 0.9}), w_o = Normalize(Vec3{-0.5, 0.1, 0.4});
  Vec3 h;
  ASSERT_TRUE(UpperHalfVector(w_i, w_o, &h));
  EXPECT_NEAR(Dot(h, w_i), Dot(h, w_o), 1e-15);
  EXPECT_NEAR(Length(h), 1.0, 1e-15);
  EXPECT_GT(h.z, 0.0);
  const Vec3 below = Normalize(Vec3{0.9, 0.1, -0.8});
  ASSERT_TRUE(UpperHalfVector(below, Normalize(Vec3{0.2, 0.3, 0.1}), &h));
  EXPECT_GE(h.z, 0.0);
  EXPECT_FALSE(UpperHalfVector(w_o, -w_o, &h));
  // Reflecting w_o about its half vector with w_i gives w_i back.
  ASSERT_TRUE(UpperHalfVector(w_i, w_o, &h));
  const Vec3 back = ReflectAboutHalfVector(w_o, h);
  EXPECT_NEAR(back.x, w_i.x, 1e-15);
  EXPECT_NEAR(back.y, w_i.y, 1e-15);
  EXPECT_NEAR(back.z, w_i.z, 1e-15);
}

TEST(HalfVectorTest, JacobianOfTheReflectionMatchesFiniteDifferences) {
  // |d w_i / d w_h| = 4 |w_o.h|: the ratio of the areas spanned by the theta and phi partial
  // derivatives of w_i(h) and of h, by central differences (error O(step^2) ~ 1e-10).
  const Vec3 w_o = Normalize(Vec3{0.4, -0.3, 0.7});
  const double step = 1e-5;
  for (const auto& [theta, phi] : {std::pair{0.3, 1.0}, {0.8, 4.0}, {1.2, 2.5}}) {
    const auto h_at = [](double t, double p) { return SphericalDirection(t, p); };
    const auto w_at = [&](double t, double p) { return ReflectAboutHalfVector(w_o, h_at(t, p)); };
    const Vec3 dh_t = (h_at(theta + step, phi) - h_at(theta - step, phi)) / (2 * step);
    const Vec3 dh_p = (h_at(theta, phi + step) - h_at(theta, phi - step)) / (2 * step);
    const Vec3 dw_t = (w_at(theta + step, phi) - w_at(theta - step, phi)) / (2 * step);
    const Vec3 dw_p = (w_at(theta, phi + step) - w_at(theta, phi - step)) / (2 * step);
    const double ratio = Length(Cross(dw_t, dw_p)) / Length(Cross(dh_t, dh_p));
    const Vec3 h = h_at(theta, phi);
    EXPECT_NEAR(ratio, 4.0 * std::abs(Dot(w_o, h)), 1e-6);
    EXPECT_NEAR(HalfVectorToIncidentPdf(1.0, w_o, h), 1.0 / ratio, 1e-6);
  }
}

TEST(ChiSquareHelperTest, PValuesMatchClosedForms) {
  // dof = 2: Q(1, x/2) = exp(-x/2); dof = 4: (1 + x/2) exp(-x/2).
  for (double x : {0.5, 2.0, 7.0, 30.0}) {
    EXPECT_NEAR(testing::ChiSquarePValue(x, 2), std::exp(-x / 2), 1e-13);
    EXPECT_NEAR(testing::ChiSquarePValue(x, 4), (1 + x / 2) * std::exp(-x / 2), 1e-13);
  }
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
