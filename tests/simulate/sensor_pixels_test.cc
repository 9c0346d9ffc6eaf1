#include "simulate/sensor_pixels.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// Rates (electrons/s at a 1 s exposure) of every kind a frame has, from SplitMix64 words (fixed
// seed): zero (off the sample) in runs, negative, Poisson counts (below 30 electrons), both sides
// of 30, shot noise up to and beyond the full well.
std::vector<float> MixedRates(size_t n, uint64_t seed) {
  std::vector<float> rates(n);
  uint64_t state = seed;
  for (size_t i = 0; i < n; ++i) {
    state = HashMix(state);
    const double u = UniformFromHash(state);
    switch (state % 10) {
      case 0:
      case 1:
      case 2:
        rates[i] = 0.0f;
        break;
      case 3:
        rates[i] = static_cast<float>(-5 * u);
        break;
      case 4:
      case 5:
        rates[i] = static_cast<float>(30 * u);
        break;
      case 6:
        rates[i] = (state >> 8) % 2 ? 30.0f : 29.999998f;
        break;
      case 7:
      case 8:
        rates[i] = static_cast<float>(30 + 3e4 * u);
        break;
      default:
        rates[i] = static_cast<float>(3e4 + 1e5 * u);
        break;
    }
  }
  // A run of zeros four pixels long and more, as off the sample.
  for (size_t i = n / 3; i < n / 3 + 41; ++i) rates[i] = 0.0f;
  return rates;
}

SensorPixelModel Model(bool add_noise) {
  SensorPixelModel m;
  m.exposure_s = 1;
  m.read_noise_e = 6.5;
  m.full_well_e = 5e4;
  m.dark_level_dn = 64;
  m.gain_e_per_dn = 12.2;
  m.max_dn = 4000;
  m.key = 0x5eed;
  m.add_noise = add_noise;
  return m;
}

TEST(SensorPixelsTest, EveryPathGivesTheSameCountsBitForBit) {
  // 100003 pixels (a tail of 3 after the groups of 4) from a large first index; the ziggurat's
  // rejections (1.2% of draws) and the Poisson counts go through the scalar path inside the
  // vector one. Rendering in chunks at any offset gives the same counts: pixels are independent.
  const std::vector<float> rates = MixedRates(100003, 9);
  for (bool noise : {true, false}) {
    const SensorPixelModel m = Model(noise);
    const int64_t first = 123456789;
    std::vector<uint16_t> fast(rates.size()), scalar(rates.size()), chunked(rates.size());
    RenderSensorPixels(rates, first, m, fast.data());
    RenderSensorPixelsScalar(rates, first, m, scalar.data());
    for (size_t begin = 0; begin < rates.size(); begin += 1001) {
      const size_t count = std::min<size_t>(1001, rates.size() - begin);
      RenderSensorPixels(std::span<const float>(rates.data() + begin, count),
                         first + static_cast<int64_t>(begin), m, chunked.data() + begin);
    }
    ASSERT_EQ(fast, scalar) << (noise ? "noise" : "no noise");
    ASSERT_EQ(chunked, scalar) << (noise ? "noise" : "no noise");
    if (noise) {
      // Not all zero or all clipped: the counts spread over the range.
      int64_t low = 0, high = 0;
      for (uint16_t c : scalar) (c < 64 ? low : high) += c > 0 && c < 4000;
      EXPECT_GT(low, 1000);
      EXPECT_GT(high, 40000);
    }
  }
}

TEST(SensorPixelsTest, NoiseFreeCountsAreTheRoundedClippedSignal) {
  // Gain 2, black level 10, full well 100 electrons, largest count 55: electrons 5 -> 12.5 -> 12
  // and 7 -> 13.5 -> 14 (ties to even), 6.2 -> 13.1 -> 13, 150 -> the full well, 60 -> 55 (the
  // clip), a negative rate -> 0 electrons -> 10; at a 0.5 s exposure half the electrons.
  SensorPixelModel m = Model(false);
  m.gain_e_per_dn = 2;
  m.dark_level_dn = 10;
  m.full_well_e = 100;
  m.max_dn = 55;
  const std::vector<float> rates = {5, 7, 6.2f, 150, -3, 0, 5, 7};
  const std::vector<uint16_t> expected = {12, 14, 13, 55, 10, 10, 12, 14};
  std::vector<uint16_t> counts(rates.size());
  RenderSensorPixels(rates, 0, m, counts.data());
  EXPECT_EQ(counts, expected);
  m.max_dn = 4095;
  RenderSensorPixels(rates, 0, m, counts.data());
  EXPECT_EQ(counts[3], 60);  // 10 + 100 / 2: the full well, not the clip
  m.exposure_s = 0.5;
  RenderSensorPixels(rates, 0, m, counts.data());
  EXPECT_EQ(counts[0], 11);  // 2.5 electrons -> 11.25 -> 11
  EXPECT_EQ(counts[1], 12);  // 3.5 -> 11.75 -> 12
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
