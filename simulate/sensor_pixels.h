// The sensor model of a simulated frame: each pixel's mean photo-electron rate to a raw count,
// with shot noise, read noise, full well, black level, quantization and clipping
// (docs/simulator.md, "A frame"). After the transport's product, the inner loop of every
// simulated frame: a full-resolution frame is a million pixels.
#pragma once

#include <cstdint>
#include <span>

#include "rig/rig.h"

namespace zbrdf {

// Counter-based random numbers (SplitMix64's finalizer): the same (key, index) always gives the
// same value.
inline uint64_t HashMix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
inline double UniformFromHash(uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

struct SensorPixelModel {
  double exposure_s = 0;
  double read_noise_e = 0;   // standard deviation, electrons
  double full_well_e = 0;    // electrons a pixel holds
  double dark_level_dn = 0;  // black level, counts
  double gain_e_per_dn = 1;  // electrons per count
  double max_dn = 4095;      // the largest count, an integer: saturation or 2^bits - 1
  uint64_t key = 0;       // the frame's noise: pixel p draws from HashMix(key + p * 2^64/phi)
  bool add_noise = true;  // false: only full well, black level, quantization and clipping

  // The rig's sensor at an exposure (key 0, noise on). A fractional saturation level clips to
  // the count below it.
  static SensorPixelModel Of(const SensorParams& sensor, double exposure_s);
};

// Raw counts of pixels first .. first + rate.size() - 1 from their mean rates (electrons/s):
// mu = max(0, rate * exposure) electrons; with noise, below 30 a Poisson count of mean mu (by
// multiplication of uniforms, Knuth), else mu + sqrt(mu) N(0, 1), at least 0 (its variance is
// exact, its skew < 1/sqrt(30)), capped at the full well, plus read noise read_noise N(0, 1)
// (standard normals by the ziggurat method, simulate/normal_sampler.h); then black level +
// electrons / gain, clamped to [0, max_dn] and rounded to nearest, ties to even. With AVX2
// (chosen when the program starts) four pixels at a time; both paths give the same counts bit
// for bit.
void RenderSensorPixels(std::span<const float> rate, int64_t first, const SensorPixelModel& model,
                        uint16_t* out);
void RenderSensorPixelsScalar(std::span<const float> rate, int64_t first,
                              const SensorPixelModel& model, uint16_t* out);

}  // namespace zbrdf
