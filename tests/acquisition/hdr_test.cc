#include "acquisition/hdr.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "basis/error.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// A small sensor: 12 bits, black 64 DN, 2.5 e-/DN, 10 e- read noise (the thesis camera's).
RigCalibration Sensor(int width, int height) {
  RigCalibration c;
  c.camera_width = width;
  c.camera_height = height;
  c.layout = PixelLayout::kMono;
  c.gain_e_per_dn = 2.5;
  c.read_noise_e = 10;
  c.black_dn = 64;
  c.saturation_dn = 4095;
  return c;
}

// Frames of a scene with electron rates `rate` (e-/s), noise-free (rounded) or with Poisson
// shot noise and Gaussian read noise.
std::vector<Frame> Bracket(const RigCalibration& c, const std::vector<double>& rate,
                           const std::vector<double>& exposures_us, std::mt19937_64* rng) {
  std::vector<Frame> frames;
  for (double t_us : exposures_us) {
    Frame f;
    f.width = c.camera_width;
    f.height = c.camera_height;
    f.layout = c.layout;
    f.bit_depth = 12;
    f.exposure_us = t_us;
    for (double r : rate) {
      double electrons = r * t_us * 1e-6;
      if (rng) {
        electrons = static_cast<double>(std::poisson_distribution<int64_t>(electrons)(*rng)) +
                    std::normal_distribution<double>(0, c.read_noise_e)(*rng);
      }
      const double dn = std::round(c.black_dn + electrons / c.gain_e_per_dn);
      f.data.push_back(static_cast<uint16_t>(std::clamp(dn, 0.0, c.saturation_dn)));
    }
    frames.push_back(std::move(f));
  }
  return frames;
}

TEST(Hdr, NoiseFreeRatesAreRecoveredAcrossTheDynamicRange) {
  const RigCalibration c = Sensor(6, 1);
  // From barely above read noise to a rate that saturates all but the shortest exposure.
  const std::vector<double> rate = {2e3, 5e4, 1e6, 2e7, 5e7, 9e7};
  const HdrImage hdr = MergeExposures(Bracket(c, rate, {100, 400, 1600}, nullptr), c, "test");
  for (size_t i = 0; i < rate.size(); ++i) {
    ASSERT_TRUE(hdr.valid[i]) << i;
    // Rounding to 1 DN in the longest unsaturated exposure: g / t of rate at most.
    const double t_longest = rate[i] * 1600e-6 < 0.95 * 4031 * 2.5 ? 1600e-6
                             : rate[i] * 400e-6 < 0.95 * 4031 * 2.5 ? 400e-6 : 100e-6;
    EXPECT_NEAR(hdr.rate[i], rate[i], 2.5 / t_longest + 1e-5 * rate[i]) << i;
  }
  EXPECT_EQ(hdr.saturated_pixels, 0);
}

TEST(Hdr, SinglePlainFrameIsTheLinearModel) {
  RigCalibration c = Sensor(3, 1);
  Frame f;
  f.width = 3;
  f.height = 1;
  f.layout = PixelLayout::kMono;
  f.exposure_us = 2000;
  f.data = {64, 1064, 3000};
  const HdrImage hdr = MergeExposures({f}, c, "one frame");
  for (int i = 0; i < 3; ++i) {
    const double expected = (f.data[i] - 64.0) * 2.5 / 2e-3;
    EXPECT_NEAR(hdr.rate[i], expected, 1e-6 * std::max(1.0, expected));
    // var = (X t + read^2 + g^2/12) / t^2 at the estimate X.
    const double var = (expected * 2e-3 + 100 + 2.5 * 2.5 / 12) / (2e-3 * 2e-3);
    EXPECT_NEAR(hdr.variance[i], var, 1e-5 * var);
  }
}

TEST(Hdr, SaturatedEverywhereIsInvalidNeverNan) {
  const RigCalibration c = Sensor(2, 1);
  const HdrImage hdr = MergeExposures(Bracket(c, {1e10, 1e5}, {100, 400}, nullptr), c, "sat");
  EXPECT_FALSE(hdr.valid[0]);
  EXPECT_EQ(hdr.rate[0], 0.0f);
  EXPECT_TRUE(hdr.valid[1]);
  EXPECT_EQ(hdr.saturated_pixels, 1);
}

TEST(Hdr, VarianceAndBiasMatchMonteCarlo) {
  // 20000 noisy brackets of one rate: the reported variance must match the spread of the
  // estimates, and the inverse-variance mean must be unbiased (within 4 standard errors).
  const RigCalibration c = Sensor(20000, 1);
  std::mt19937_64 rng(20240607);
  for (double rate : {3e4, 4e6}) {
    const std::vector<double> rates(20000, rate);
    const HdrImage hdr = MergeExposures(Bracket(c, rates, {250, 1000, 4000}, &rng), c, "mc");
    double mean = 0, reported = 0;
    for (int i = 0; i < 20000; ++i) {
      mean += hdr.rate[i];
      reported += hdr.variance[i];
    }
    mean /= 20000;
    reported /= 20000;
    double spread = 0;
    for (int i = 0; i < 20000; ++i) spread += (hdr.rate[i] - mean) * (hdr.rate[i] - mean);
    spread /= 19999;
    EXPECT_NEAR(mean, rate, 4 * std::sqrt(spread / 20000)) << rate;
    // The sample variance of 20000 draws is within ~3% (4 sigma) of the truth.
    EXPECT_NEAR(reported / spread, 1.0, 0.05) << rate;
  }
}

TEST(Hdr, BadFramesAreNamedInputErrors) {
  const RigCalibration c = Sensor(4, 1);
  std::vector<Frame> frames = Bracket(c, {1e5, 1e5, 1e5, 1e5}, {100, 400}, nullptr);
  EXPECT_THROW(MergeExposures({}, c, "none"), InputError);
  std::vector<Frame> bad = frames;
  bad[1].exposure_us = std::nan("");
  EXPECT_THROW(MergeExposures(bad, c, "nan exposure"), InputError);
  bad = frames;
  bad[0].width = 2;
  EXPECT_THROW(MergeExposures(bad, c, "size"), InputError);
  bad = frames;
  bad[1].data[2] = 5000;  // above 12 bits
  try {
    MergeExposures(bad, c, "lobe Z2,1+");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lobe Z2,1+"), std::string::npos);
  }
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
