// The piecewise-bilinear warp of the RGL format: normalization, Invert as the inverse of
// Sample, the sampled distribution against the density, and parameter interpolation.
#include "brdf/bilinear_warp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "basis/error.h"
#include "brdf_checks.h"
#include "tests/test_files.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

std::vector<float> Bumpy(int nx, int ny, double phase) {
  std::vector<float> v(static_cast<size_t>(nx) * ny);
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      v[static_cast<size_t>(y) * nx + x] =
          static_cast<float>(0.2 + std::exp(-20 * std::pow(x / (nx - 1.0) - 0.3 - phase, 2)) *
                                       (1 + std::sin(6.0 * y / ny + phase)));
    }
  }
  return v;
}

TEST(BilinearWarp, DensityIntegratesToOne) {
  const BilinearWarp2D warp(9, 7, Bumpy(9, 7, 0.0), {}, true);
  // The density is bilinear per cell, so a 2 x 2 Gauss-Legendre rule per cell is exact.
  const double g = 0.5 / std::sqrt(3.0);
  double integral = 0;
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 8; ++x) {
      for (double sx : {-g, g}) {
        for (double sy : {-g, g}) {
          integral += warp.Eval({(x + 0.5 + sx) / 8, (y + 0.5 + sy) / 6}) / 48 / 4;
        }
      }
    }
  }
  EXPECT_NEAR(integral, 1.0, 1e-12);
}

TEST(BilinearWarp, InvertUndoesSampleAndReportsTheSameDensity) {
  const std::vector<std::vector<float>> params = {{0.0f, 1.0f, 3.0f}};
  std::vector<float> values;
  for (double phase : {0.0, 0.2, 0.4}) {
    const auto v = Bumpy(12, 10, phase);
    values.insert(values.end(), v.begin(), v.end());
  }
  const BilinearWarp2D warp(12, 10, values, params, true);
  testing::Rng rng(1);
  for (int k = 0; k < 2000; ++k) {
    const double p[1] = {3.2 * rng.Uniform() - 0.1};  // also beyond the ends (clamped)
    const std::array<double, 2> u = {rng.Uniform(), rng.Uniform()};
    const auto s = warp.Sample(u, p);
    const auto back = warp.Invert({s[0], s[1]}, p);
    ASSERT_NEAR(back[0], u[0], 1e-9);
    ASSERT_NEAR(back[1], u[1], 1e-9);
    ASSERT_NEAR(back[2], s[2], 1e-9 * s[2]);
    ASSERT_NEAR(warp.Eval({s[0], s[1]}, p), s[2], 1e-9 * s[2]);
  }
}

TEST(BilinearWarp, SamplesFollowTheDensity) {
  // Histogram of 200000 samples on a 16 x 16 grid against the integral of the density over each
  // bin; Pearson chi-square with 255 degrees of freedom, threshold at p = 1e-4 (~350).
  const BilinearWarp2D warp(6, 5, Bumpy(6, 5, 0.1), {}, true);
  const int bins = 16, n = 200000;
  std::vector<double> counts(bins * bins, 0.0);
  testing::Rng rng(2);
  for (int k = 0; k < n; ++k) {
    const auto s = warp.Sample({rng.Uniform(), rng.Uniform()});
    counts[std::min(bins - 1, static_cast<int>(s[1] * bins)) * bins +
           std::min(bins - 1, static_cast<int>(s[0] * bins))] += 1;
  }
  double chi2 = 0;
  for (int by = 0; by < bins; ++by) {
    for (int bx = 0; bx < bins; ++bx) {
      double expected = 0;
      const int m = 8;  // midpoint rule inside the bin: the density is smooth at this scale
      for (int i = 0; i < m; ++i) {
        for (int j = 0; j < m; ++j) {
          expected += warp.Eval({(bx + (i + 0.5) / m) / bins, (by + (j + 0.5) / m) / bins});
        }
      }
      expected *= n / static_cast<double>(m * m * bins * bins);
      chi2 += std::pow(counts[by * bins + bx] - expected, 2) / expected;
    }
  }
  EXPECT_LT(chi2, 350);
}

TEST(BilinearWarp, InterpolatesBetweenParameterSlices) {
  std::vector<float> values(2 * 4, 0.0f);
  for (int i = 0; i < 4; ++i) {
    values[i] = 1.0f;      // slice 0: constant 1
    values[4 + i] = 3.0f;  // slice 1: constant 3
  }
  const BilinearWarp2D table(2, 2, values, {{10.0f, 20.0f}}, false);
  const double at_12[1] = {12.0}, below[1] = {0.0}, above[1] = {99.0};
  EXPECT_NEAR(table.Eval({0.3, 0.7}, at_12), 1.4, 1e-12);
  EXPECT_NEAR(table.Eval({0.3, 0.7}, below), 1.0, 1e-12);
  EXPECT_NEAR(table.Eval({0.3, 0.7}, above), 3.0, 1e-12);
}

TEST(BilinearWarp, RejectsBadInput) {
  EXPECT_THROW(BilinearWarp2D(1, 4, std::vector<float>(4, 1.0f), {}, true), InputError);
  EXPECT_THROW(BilinearWarp2D(2, 2, std::vector<float>(3, 1.0f), {}, true), InputError);
  EXPECT_THROW(BilinearWarp2D(2, 2, std::vector<float>{1, -1, 1, 1}, {}, true), InputError);
  EXPECT_THROW(BilinearWarp2D(2, 2, std::vector<float>(8, 1.0f), {{1.0f, 1.0f}}, true), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
