// Tests of pictures/relight.h: the SMC building blocks against hand-computed cases, the furnace,
// and each sampler's unbiasedness (mean over seeds against a converged reference, within the
// standard errors of both).
#include "pictures/relight.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "basis/error.h"
#include "brdf/dbrdf.h"
#include "brdf/lambertian.h"
#include "brdf/material_spec.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

TEST(Relight, ReweightingMatchesAHandComputedCase) {
  // Four equally weighted particles, incremental weights 1, 2, 3, 4: the normalizing constant
  // grows by their mean, 2.5; the weights become 0.1, 0.2, 0.3, 0.4; ESS = 1 / 0.3.
  std::vector<double> w = {0.25, 0.25, 0.25, 0.25};
  const std::vector<double> inc = {1, 2, 3, 4};
  const Reweighting r = ReweightParticles(w, inc);
  EXPECT_DOUBLE_EQ(r.z_factor, 2.5);
  EXPECT_NEAR(w[0], 0.1, 1e-15);
  EXPECT_NEAR(w[1], 0.2, 1e-15);
  EXPECT_NEAR(w[2], 0.3, 1e-15);
  EXPECT_NEAR(w[3], 0.4, 1e-15);
  EXPECT_NEAR(r.ess, 1.0 / 0.3, 1e-12);
  // Unequal weights: (0.5, 0.5, 0, 0) x (2, 0, 5, 1): factor 1, weights (1, 0, 0, 0), ESS 1.
  std::vector<double> w2 = {0.5, 0.5, 0, 0};
  const Reweighting r2 = ReweightParticles(w2, std::vector<double>{2, 0, 5, 1});
  EXPECT_DOUBLE_EQ(r2.z_factor, 1.0);
  EXPECT_DOUBLE_EQ(w2[0], 1.0);
  EXPECT_DOUBLE_EQ(r2.ess, 1.0);
  // Every weight lost: factor 0, weights untouched.
  std::vector<double> w3 = {0.5, 0.5};
  const Reweighting r3 = ReweightParticles(w3, std::vector<double>{0, 0});
  EXPECT_EQ(r3.z_factor, 0.0);
  EXPECT_EQ(r3.ess, 0.0);
  EXPECT_EQ(w3[0], 0.5);
}

TEST(Relight, SystematicResamplingMatchesAHandComputedCase) {
  // Cumulative weights 0.1, 0.3, 0.6, 1.0; points (k + 0.5) / 4 = 0.125, 0.375, 0.625, 0.875.
  const std::vector<double> w = {0.1, 0.2, 0.3, 0.4};
  std::vector<int> idx(4);
  SystematicResample(w, 0.5, idx);
  EXPECT_EQ(idx, (std::vector<int>{1, 2, 3, 3}));
  // u = 0: points 0, 0.25, 0.5, 0.75 -> cells 0, 1, 2, 3.
  SystematicResample(w, 0.0, idx);
  EXPECT_EQ(idx, (std::vector<int>{0, 1, 2, 3}));
  // Each index appears floor or ceil of N w_i times, for any u.
  const std::vector<double> w8 = {0.05, 0.3, 0.15, 0.5};
  std::vector<int> idx8(8);
  for (double u : {0.0, 0.13, 0.5, 0.77, 0.999}) {
    SystematicResample(w8, u, idx8);
    for (int i = 0; i < 4; ++i) {
      const int count = static_cast<int>(std::count(idx8.begin(), idx8.end(), i));
      EXPECT_GE(count, static_cast<int>(std::floor(8 * w8[i])));
      EXPECT_LE(count, static_cast<int>(std::ceil(8 * w8[i])));
    }
  }
}

// The mean over the ball's interior pixels (those whose 3x3 neighbourhood is on the ball).
std::vector<size_t> Interior(const BallImage& image) {
  const int size = image.image.width;
  std::vector<size_t> out;
  for (int y = 1; y + 1 < size; ++y) {
    for (int x = 1; x + 1 < size; ++x) {
      bool all = true;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          all = all && image.coverage[static_cast<size_t>(y + dy) * size + x + dx];
        }
      }
      if (all) out.push_back(static_cast<size_t>(y) * size + x);
    }
  }
  return out;
}

TEST(Relight, FurnaceLambertianUnderConstantLight) {
  // A Lambertian ball under a constant environment reflects albedo x radiance at every pixel.
  // With every candidate from the BRDF's (cosine-weighted) sampler, each candidate's weight is
  // (L + eps) exactly, and the estimate Z (1/N) sum f cos L / g = albedo L to rounding: each pixel
  // within 1e-6 relative (SMC keeps its particles in single precision), on every frame, for SIR,
  // SMC and SMC bridges (SMC's pool weights then add up to
  // Z_t = (M (L + eps) + C Z_{t-1}) / (M + C) = L + eps). The frames are either a turning map
  // (Rotated copies) or maps of their own; on the turning map SMC turns its particles with the
  // light, away from where the cosine put them, so its weights are no longer constant and only
  // its mean is checked (below).
  // With the default mixture, environment candidates (uniform over the sphere) spread the
  // weights: each pixel's relative standard error is about 3% at 256 candidates, and the mean
  // over ~290 interior pixels is within 0.5% (more than 3 standard errors).
  const LambertianBrdf brdf(Rgb(0.2, 0.5, 0.8));
  const Rgb radiance(2.0, 1.0, 0.5);
  const Rgb expected(0.2 * 2.0, 0.5 * 1.0, 0.8 * 0.5);
  const Environment env = Environment::Constant(radiance);
  for (BallSampler sampler : {BallSampler::kSir, BallSampler::kSmc, BallSampler::kSmcBridges}) {
    for (bool turning : {true, false}) {
      for (double share : {1.0, 0.5}) {
        RelightOptions options;
        options.ball.size = 24;
        options.ball.spp = 64;
        options.sampler = sampler;
        options.brdf_candidate_share = share;
        BallSequence sequence(brdf, options);
        const bool exact = share == 1.0 && !(turning && sampler == BallSampler::kSmc);
        for (int frame = 0; frame < 3; ++frame) {
          const BallImage image = sequence.Render(
              turning ? env.Rotated(0.3 * frame) : Environment::Constant(radiance));
          const std::vector<size_t> interior = Interior(image);
          ASSERT_GT(interior.size(), 250u);
          Rgb mean;
          for (size_t i : interior) {
            if (exact) {
              for (int c = 0; c < 3; ++c) {
                ASSERT_NEAR(image.image.pixels[i][c], expected[c], 1e-6 * expected[c])
                    << "sampler " << BallSamplerName(sampler) << " turning " << turning
                    << " frame " << frame;
              }
            }
            mean += image.image.pixels[i] / static_cast<double>(interior.size());
          }
          for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(mean[c], expected[c], 0.005 * expected[c])
                << "sampler " << BallSamplerName(sampler) << " turning " << turning << " share "
                << share << " frame " << frame;
          }
        }
      }
    }
  }
}

// A high-frequency environment: a dim room (0.05) with a small bright source (radiance 60,
// about 6 deg across) and a broad dimmer one.
Environment SmallSource() {
  RgbImage image(128, 64);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 128; ++x) {
      Rgb c(0.05, 0.05, 0.06);
      if (x >= 70 && x < 72 && y >= 20 && y < 22) c = Rgb(60, 55, 50);
      if (x >= 30 && x < 44 && y >= 10 && y < 24) c = Rgb(1.5, 1.6, 2.0);
      image.At(x, y) = c;
    }
  }
  return Environment(std::move(image));
}

DBrdf GlossyDBrdf() {
  DBrdfParams params;
  params.p_h = HalfVectorTable::Ggx(0.15);
  params.c = Rgb(0.25, 0.2, 0.15);
  params.f0 = 0.9;
  params.kd = Rgb(0.05, 0.1, 0.2);
  return DBrdf(params);
}

// A smooth map: a dim sky (0.2) with one broad bright lobe (up to ~3, some 30 deg wide).
Environment SmoothLobe() {
  RgbImage image(128, 64);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 128; ++x) {
      const double u = 2 * M_PI * x / 128, v = M_PI * (y + 0.5) / 64;
      const double a = 0.2 + 3.0 * std::exp(3.0 * std::cos(u - 1.0) * std::sin(v) - 3.0);
      image.At(x, y) = Rgb(a, 0.9 * a, 0.8 * a);
    }
  }
  return Environment(std::move(image));
}

// Unbiasedness: frame `frames - 1` of a turning map (0.2 rad per frame), averaged over 120 seeds,
// against a MIS reference (16 runs of 2^12 samples per pixel at the pixel centres), on the four
// quadrants of a 12-pixel ball and each RGB channel: each mean over a quadrant's pixels and the
// seeds must be within 4.5 combined standard errors of the reference (12 statistics; with the
// reference's standard error estimated from 16 runs, |t| > 4.5 has probability ~4e-4 each). Per-quadrant means rather than per-pixel ones: their
// distribution over seeds is close to normal, so the standard error estimated from 120 seeds is
// trustworthy. With copies, the frames are Rotated copies of base (a turntable: SMC turns its
// particles with the light); without, each frame is a map of its own with the same pixels (an
// HDR sequence: SMC carries them unturned).
void ExpectUnbiased(BallSampler sampler, const Environment& base, int frames,
                    bool copies = true) {
  const DBrdf brdf = GlossyDBrdf();
  const double step = 0.2;
  const Environment last = base.Rotated(step * (frames - 1));
  const int size = 12;
  auto quadrant = [&](size_t i) {
    return static_cast<int>((i % size) * 2 / size) + 2 * static_cast<int>((i / size) * 2 / size);
  };
  // Per-quadrant, per-channel means of one image over its ball pixels.
  auto region_means = [&](const BallImage& image) {
    std::array<double, 12> sum{}, count{};
    for (size_t i = 0; i < image.image.pixels.size(); ++i) {
      if (!image.coverage[i]) continue;
      for (int c = 0; c < 3; ++c) {
        sum[quadrant(i) * 3 + c] += image.image.pixels[i][c];
        count[quadrant(i) * 3 + c] += 1;
      }
    }
    for (int k = 0; k < 12; ++k) sum[k] /= count[k];
    return sum;
  };
  auto stats = [](const std::vector<std::array<double, 12>>& runs, int k, double* se) {
    double m = 0, m2 = 0;
    for (const auto& r : runs) m += r[k] / runs.size();
    for (const auto& r : runs) m2 += (r[k] - m) * (r[k] - m);
    *se = std::sqrt(m2 / (runs.size() - 1) / runs.size());
    return m;
  };
  std::vector<std::array<double, 12>> refs, runs;
  BallOptions ref_options;
  ref_options.size = size;
  ref_options.jitter = false;
  ref_options.spp = 1 << 12;
  for (int r = 0; r < 16; ++r) {
    ref_options.seed = 99 + r;
    refs.push_back(region_means(RenderBall(brdf, &last, ref_options)));
  }
  for (int s = 0; s < 120; ++s) {
    RelightOptions options;
    options.ball.size = size;
    options.ball.spp = 4;
    options.ball.seed = 1000 + s;
    options.sampler = sampler;
    BallSequence sequence(brdf, options);
    BallImage image;
    for (int t = 0; t < frames; ++t) {
      image = copies ? sequence.Render(base.Rotated(step * t))
                     : sequence.Render(Environment(base.image(), step * t));
    }
    runs.push_back(region_means(image));
  }
  for (int k = 0; k < 12; ++k) {
    double se = 0, se_ref = 0;
    const double mean = stats(runs, k, &se), ref = stats(refs, k, &se_ref);
    const double z = (mean - ref) / std::sqrt(se * se + se_ref * se_ref);
    EXPECT_LT(std::abs(z), 4.5) << "quadrant " << k / 3 << " channel " << k % 3 << ": mean "
                                << mean << " +- " << se << ", reference " << ref << " +- "
                                << se_ref;
  }
}

// SIR under the high-frequency map (a small source 1200 times the room's radiance).
TEST(Relight, SirIsUnbiased) { ExpectUnbiased(BallSampler::kSir, SmallSource(), 1); }
// SMC after 3 transitions, under the high-frequency map: its pool weights are bounded (carried
// <= Z_{t-1} / N, fresh <= g_t / (M q)), so the source moving by more than its size between
// frames does not make them heavy-tailed.
TEST(Relight, SmcIsUnbiasedAfterSeveralFrames) {
  ExpectUnbiased(BallSampler::kSmc, SmallSource(), 4);
}
// The same frames as maps of their own (Environment::TurnSince knows no turn): the particles stay
// where they were and g_{t-1} is looked up in the previous map.
TEST(Relight, SmcIsUnbiasedOverASequenceOfMaps) {
  ExpectUnbiased(BallSampler::kSmc, SmallSource(), 4, /*copies=*/false);
}
// SMC bridges after 3 transitions. Its estimate is unbiased under any map, but under SmallSource
// the incremental weights are heavy-tailed (a source that moves by more than its size between
// frames lands on a particle only rarely, with a weight up to 1200), so 120 seeds cannot estimate
// its standard error; the smooth map keeps the test's statistics sound (docs/preview.md).
TEST(Relight, SmcBridgesIsUnbiasedAfterSeveralFrames) {
  ExpectUnbiased(BallSampler::kSmcBridges, SmoothLobe(), 4);
}

TEST(Relight, SmcWeightsMatchAHandComputedCase) {
  // M = 4 fresh candidates, N = 2 carried particles, C = 4 (history weight 1).
  // A fresh candidate with g_t = 3, g_{t-1} = 1, q = 2: 3^2 / ((4 * 3 + 4 * 1) * 2) = 9 / 32.
  EXPECT_DOUBLE_EQ(FreshCandidateWeight(3, 1, 2, 4, 4), 9.0 / 32.0);
  // A carried particle with g_t = 3, g_{t-1} = 1, Z_{t-1} = 5: (4 / 2) * 3 * 5 / 16 = 15 / 8.
  EXPECT_DOUBLE_EQ(CarriedParticleWeight(3, 1, 5, 2, 4, 4), 15.0 / 8.0);
  // Light that left a particle (g_t = 0) takes all its weight; light that appeared at a fresh
  // candidate (g_{t-1} = 0) gives it the plain SIR weight g_t / (M q).
  EXPECT_EQ(CarriedParticleWeight(0, 1, 5, 2, 4, 4), 0.0);
  EXPECT_DOUBLE_EQ(FreshCandidateWeight(3, 0, 2, 4, 4), 3.0 / 8.0);
  // No history (C = 0): SIR's weights g / (M q).
  EXPECT_DOUBLE_EQ(FreshCandidateWeight(3, 7, 2, 4, 0), 3.0 / 8.0);
  // The two groups' balance-heuristic weights are a partition of unity at every direction:
  // M m_fresh + N m_carried = (M g_t + C g_prev) / D = 1, i.e. with unit contribution weights
  // (q = 1, Z_{t-1} = g_prev) the weights of M fresh copies and N carried copies of one
  // direction add up to g_t.
  for (double g_t : {0.1, 1.0, 30.0}) {
    for (double g_prev : {0.05, 1.0, 50.0}) {
      for (double c : {0.5, 4.0, 40.0}) {
        const int m = 4, n = 3;
        const double fresh = FreshCandidateWeight(g_t, g_prev, 1.0, m, c);
        const double carried = CarriedParticleWeight(g_t, g_prev, g_prev, n, m, c);
        EXPECT_NEAR(m * fresh + n * carried, g_t, 1e-12 * g_t)
            << g_t << " " << g_prev << " " << c;
      }
    }
  }
}

TEST(Relight, SmcOnAStillEnvironmentAveragesOverFrames) {
  // Nothing changes between frames: the carried particles' weights add up to C / (M + C) Z_{t-1}
  // and the fresh candidates' to M / (M + C) of a new SIR estimate F_t, so with C = M
  //   Z_t = F_t / 2 + Z_{t-1} / 2,  Z_0 = F_0,
  // a running average whose variance at frame 6 is sum_{j=1..6} 4^-j + 4^-6 = 0.3335 of frame
  // 0's. For a Lambertian material f cos / g = albedo L / (L + eps) is constant to 1e-3, so a
  // pixel's estimate is Z_t times a constant and its variance over seeds follows Z_t's. Summed
  // over ~250 pixels of 40 seeds each, the ratio of variances has a relative standard error of
  // about 2%: it must be within 0.30-0.37, and the mean must not move (1%).
  const LambertianBrdf brdf(Rgb(0.5));
  const Environment env = SmoothLobe();
  const int size = 20, seeds = 40;
  std::vector<std::vector<Rgb>> first, later;
  std::vector<uint8_t> coverage;
  for (int s = 0; s < seeds; ++s) {
    RelightOptions options;
    options.ball.size = size;
    options.ball.spp = 4;
    options.ball.seed = 500 + s;
    options.sampler = BallSampler::kSmc;
    BallSequence sequence(brdf, options);
    RelightStats stats;
    first.push_back(sequence.Render(env, &stats).image.pixels);
    EXPECT_GT(stats.sir_starts, 0);
    BallImage image;
    for (int t = 1; t <= 6; ++t) image = sequence.Render(env, &stats);
    EXPECT_EQ(stats.sir_starts, 0);
    EXPECT_GT(stats.carried, 0);
    later.push_back(image.image.pixels);
    if (s == 0) coverage = image.coverage;
  }
  double var_first = 0, var_later = 0, mean_first = 0, mean_later = 0;
  for (size_t i = 0; i < first[0].size(); ++i) {
    if (!coverage[i]) continue;
    double a = 0, a2 = 0, b = 0, b2 = 0;
    for (int s = 0; s < seeds; ++s) {
      const double x = first[s][i].Luminance(), y = later[s][i].Luminance();
      a += x;
      a2 += x * x;
      b += y;
      b2 += y * y;
    }
    mean_first += a;
    mean_later += b;
    var_first += (a2 - a * a / seeds) / (seeds - 1);
    var_later += (b2 - b * b / seeds) / (seeds - 1);
  }
  EXPECT_GT(var_later / var_first, 0.30);
  EXPECT_LT(var_later / var_first, 0.37);
  EXPECT_NEAR(mean_later / mean_first, 1.0, 0.01);
}

TEST(Relight, SmcBridgesOnAStillEnvironmentKeepsItsEstimate) {
  // Nothing changes between frames: the incremental weights are 1, the normalizing constant is
  // carried unchanged, and MH moves keep the particles distributed as the target, so frame 5's
  // mean over the ball equals frame 0's within Monte Carlo error (relative 2%: ~300 pixels of
  // 32 particles each).
  const DBrdf brdf = GlossyDBrdf();
  const Environment env = SmallSource();
  RelightOptions options;
  options.ball.size = 24;
  options.ball.spp = 32;
  options.sampler = BallSampler::kSmcBridges;
  BallSequence sequence(brdf, options);
  RelightStats stats;
  const BallImage first = sequence.Render(env, &stats);
  EXPECT_GT(stats.sir_starts, 0);
  BallImage later;
  for (int t = 1; t < 6; ++t) later = sequence.Render(env, &stats);
  EXPECT_EQ(stats.sir_starts, 0);
  EXPECT_EQ(stats.resamplings, 0);  // ESS stays N
  EXPECT_NEAR(stats.mean_ess_fraction, 1.0, 1e-6);
  EXPECT_GT(stats.moves_accepted, 0);
  double a = 0, b = 0;
  for (size_t i = 0; i < first.image.pixels.size(); ++i) {
    if (!first.coverage[i]) continue;
    a += first.image.pixels[i].Luminance();
    b += later.image.pixels[i].Luminance();
  }
  EXPECT_NEAR(b / a, 1.0, 0.02);
}

TEST(Relight, MirrorNeedsNoSampling) {
  const auto mirror = MakeBrdf("mirror:0.9");
  const Environment env = SmallSource();
  RelightOptions options;
  options.ball.size = 16;
  options.ball.spp = 2;
  options.sampler = BallSampler::kSmc;
  BallSequence a(*mirror, options);
  options.ball.seed = 77;
  BallSequence b(*mirror, options);
  const BallImage ia = a.Render(env), ib = b.Render(env);
  EXPECT_EQ(ia.image.pixels, ib.image.pixels);  // deterministic whatever the seed
}

TEST(Relight, RejectsBadOptions) {
  const LambertianBrdf brdf(Rgb(0.5));
  RelightOptions options;
  options.brdf_candidate_share = 0;
  EXPECT_THROW({ BallSequence s(brdf, options); }, InputError);
  options = {};
  options.bridges = 0;
  EXPECT_THROW({ BallSequence s(brdf, options); }, InputError);
  options = {};
  options.history_weight = 0;
  EXPECT_THROW({ BallSequence s(brdf, options); }, InputError);
  options = {};
  options.ball.light_direction = Vec3{0, 0, 1};
  EXPECT_THROW({ BallSequence s(brdf, options); }, InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf

