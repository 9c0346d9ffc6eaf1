#include "simulate/normal_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "simulate/imaging.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

double NormalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

// Words from SplitMix64, the simulator's own stream (fixed seed).
struct Words {
  uint64_t state;
  uint64_t operator()() { return state = HashMix(state); }
};

TEST(ZigguratNormalTest, LayersHaveTheAreaTheyAreChosenFor) {
  // Every layer is picked with probability 1/128, so each must have the area v: the rectangles
  // x_i (f(x_{i+1}) - f(x_i)), the top one included (up to f(0) = 1, where the recursion of the
  // constructor does not reach), and the base strip r f(r) + the tail's integral of f beyond r.
  const ZigguratNormal& z = ZigguratNormal::Get();
  const auto& x = z.edges();
  const auto f = [](double t) { return std::exp(-0.5 * t * t); };
  const double v = z.layer_area(), r = z.tail_start();
  // Marsaglia and Tsang's constants: r to the 13 digits they give; their v is that of their r,
  // and dv/dr = -r^2 f(r) = -0.032 turns r's last digit into 1e-13.
  EXPECT_NEAR(r, 3.442619855899, 1e-11);
  EXPECT_NEAR(v, 9.91256303526217e-3, 1e-12);
  for (int i = 1; i < ZigguratNormal::kLayers; ++i) {
    EXPECT_NEAR(x[i] * (f(x[i + 1]) - f(x[i])), v, 1e-9 * v) << "layer " << i;
    EXPECT_GT(x[i], x[i + 1]);
  }
  const double tail = std::sqrt(M_PI / 2) * std::erfc(r / std::sqrt(2.0));
  EXPECT_NEAR(r * f(r) + tail, v, 1e-9 * v);
  EXPECT_NEAR(x[0] * f(r), v, 1e-15);
}

TEST(ZigguratNormalTest, SamplesFollowTheStandardNormal) {
  // 4 M variates against the closed-form CDF: 200 equal-probability bins of (-inf, inf), whose
  // chi-square has 199 degrees of freedom (mean 199, sd 20): 300 is beyond the 99.999th
  // percentile. The tails beyond the ziggurat's r (probability 5.8e-4 for |x| > r) and beyond 4.5
  // (6.8e-6) get their share within 5 standard errors; the moments within theirs.
  const ZigguratNormal& z = ZigguratNormal::Get();
  Words words{0x5eed};
  constexpr int kSamples = 4000000, kBins = 200;
  std::vector<double> edges(kBins - 1);
  // Bin edges by bisection of the CDF at k / kBins.
  for (int k = 1; k < kBins; ++k) {
    double lo = -10, hi = 10;
    for (int it = 0; it < 100; ++it) {
      const double mid = 0.5 * (lo + hi);
      (NormalCdf(mid) < static_cast<double>(k) / kBins ? lo : hi) = mid;
    }
    edges[k - 1] = 0.5 * (lo + hi);
  }
  std::vector<int> counts(kBins, 0);
  double sum = 0, sum2 = 0, sum4 = 0;
  int beyond_r = 0, beyond_4_5 = 0;
  for (int i = 0; i < kSamples; ++i) {
    const double x = z.Sample(words);
    ASSERT_TRUE(std::isfinite(x));
    ++counts[std::upper_bound(edges.begin(), edges.end(), x) - edges.begin()];
    sum += x;
    sum2 += x * x;
    sum4 += x * x * x * x;
    beyond_r += std::abs(x) > z.tail_start();
    beyond_4_5 += std::abs(x) > 4.5;
  }
  const double expected = static_cast<double>(kSamples) / kBins;
  double chi2 = 0;
  for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
  EXPECT_LT(chi2, 300.0);
  const auto within = [&](int count, double p) {
    const double mean = kSamples * p, sd = std::sqrt(kSamples * p * (1 - p));
    EXPECT_NEAR(count, mean, 5 * sd) << "p = " << p;
  };
  within(beyond_r, std::erfc(z.tail_start() / std::sqrt(2.0)));
  within(beyond_4_5, std::erfc(4.5 / std::sqrt(2.0)));
  // Standard errors: mean 1/sqrt(n), variance sqrt(2/n), fourth moment sqrt(96/n).
  EXPECT_NEAR(sum / kSamples, 0.0, 5 / std::sqrt(kSamples));
  EXPECT_NEAR(sum2 / kSamples, 1.0, 5 * std::sqrt(2.0 / kSamples));
  EXPECT_NEAR(sum4 / kSamples, 3.0, 5 * std::sqrt(96.0 / kSamples));
}

TEST(ZigguratNormalTest, SameWordsSameVariates) {
  const ZigguratNormal& z = ZigguratNormal::Get();
  Words a{42}, b{42};
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(z.Sample(a), z.Sample(b));
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
