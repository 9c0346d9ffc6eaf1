#include "simulate/normal_sampler.h"

namespace zbrdf {
namespace {

double Density(double x) { return std::exp(-0.5 * x * x); }

// The base strip's area for a tail starting at r: the rectangle r f(r) and the tail's integral
// of f beyond r, sqrt(pi / 2) erfc(r / sqrt(2)).
double BaseArea(double r) {
  return r * Density(r) + std::sqrt(M_PI / 2) * std::erfc(r / std::sqrt(2.0));
}

// Stacks layers of the base strip's area from r upwards: x_{i+1} = sqrt(-2 ln(v / x_i + f(x_i)))
// makes x_i (f(x_{i+1}) - f(x_i)) = v. Returns how much the top layer's area x_127 (1 - f(x_127))
// exceeds v; NaN when the layers reach the top before the last one (r too small).
double TopLayerExcess(double r, std::array<double, ZigguratNormal::kLayers + 1>* x) {
  const double v = BaseArea(r);
  (*x)[0] = v / Density(r);
  (*x)[1] = r;
  for (int i = 1; i + 1 < ZigguratNormal::kLayers; ++i) {
    (*x)[i + 1] = std::sqrt(-2.0 * std::log(v / (*x)[i] + Density((*x)[i])));
  }
  (*x)[ZigguratNormal::kLayers] = 0.0;
  const double top = (*x)[ZigguratNormal::kLayers - 1];
  return top * (1.0 - Density(top)) - v;
}

}  // namespace

ZigguratNormal::ZigguratNormal() {
  // r such that the 128 layers close exactly at the top, by bisection around Marsaglia and
  // Tsang's r = 3.442619855899: a larger r makes thinner layers, whose top one is too large.
  double lo = 3.43, hi = 3.45;
  for (int it = 0; it < 200 && lo < hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    const double excess = TopLayerExcess(mid, &x_);
    (std::isnan(excess) || excess < 0 ? lo : hi) = mid;
  }
  TopLayerExcess(hi, &x_);
  area_ = BaseArea(hi);
  for (int i = 0; i <= kLayers; ++i) f_[i] = Density(x_[i]);
}

const ZigguratNormal& ZigguratNormal::Get() {
  static const ZigguratNormal tables;
  return tables;
}

}  // namespace zbrdf
