// Standard normal variates by the ziggurat method (Marsaglia and Tsang 2000, "The Ziggurat
// Method for Generating Random Variables", Journal of Statistical Software 5(8)), for the sensor
// model's read and shot noise: one frame of the full-resolution thesis rig draws 2.6 M of them,
// and Box-Muller's log and sincos were a third of a warm simulation's CPU time.
//
// The density's right half is covered by 128 layers of equal area: 127 rectangles stacked under
// the curve and a base strip (a rectangle plus the tail beyond r). A 64-bit word picks a layer
// (7 bits), a sign (1 bit) and a point across the layer (53 bits); 98.8% of the points lie
// inside the curve's rectangle and are returned at once. The rest are tested against the curve
// (a wedge) or drawn from the tail (Marsaglia 1964) with further words. The result is exactly
// N(0, 1) for independent uniform words; about 1.02 words per variate.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

namespace zbrdf {

class ZigguratNormal {
 public:
  static constexpr int kLayers = 128;

  // The tables, built once per process.
  static const ZigguratNormal& Get();

  // A standard normal variate from words drawn by next() (uint64_t, independent and uniform).
  template <typename NextWord>
  double Sample(NextWord&& next) const {
    for (;;) {
      const uint64_t word = next();
      const int layer = static_cast<int>(word & (kLayers - 1));
      const double sign = (word & kLayers) != 0 ? -1.0 : 1.0;
      const double x = Uniform(word) * x_[layer];
      if (x < x_[layer + 1]) return sign * x;  // inside the rectangle under the curve
      if (layer == 0) {
        // Beyond r: x = r + a with density exp(-r a - a^2 / 2), by rejection from exp(-r a).
        double a = 0, b = 0;
        do {
          a = -std::log(1.0 - Uniform(next())) / x_[1];
          b = -std::log(1.0 - Uniform(next()));
        } while (b + b < a * a);
        return sign * (x_[1] + a);
      }
      // The wedge between the rectangle and the curve: y uniform over the layer's height.
      if (f_[layer] + Uniform(next()) * (f_[layer + 1] - f_[layer]) < std::exp(-0.5 * x * x)) {
        return sign * x;
      }
    }
  }

  // Where the tail starts (r = 3.4426198558966...: Marsaglia and Tsang give 3.442619855899),
  // and each layer's area v, solved to double precision when the tables are built.
  double tail_start() const { return x_[1]; }
  double layer_area() const { return area_; }
  // Layer edges: x_[0] = v / f(r) (the base strip's width as if it were a rectangle),
  // x_[1] = r > x_[2] > ... > x_[kLayers] = 0; f(x) = exp(-x^2 / 2).
  const std::array<double, kLayers + 1>& edges() const { return x_; }

 private:
  ZigguratNormal();
  // The word's top 53 bits as a double in [0, 1) (the low byte picks the layer and sign).
  static double Uniform(uint64_t word) { return static_cast<double>(word >> 11) * 0x1.0p-53; }

  std::array<double, kLayers + 1> x_{}, f_{};
  double area_ = 0;
};

}  // namespace zbrdf
