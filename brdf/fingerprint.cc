#include "brdf/fingerprint.h"

#include <cmath>
#include <cstdio>
#include <vector>

#include "basis/hash.h"

namespace zbrdf {
namespace {

Vec3 Direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

template <typename T>
uint64_t Mix(uint64_t h, const T& value) {
  return Fnv1a64(&value, sizeof(value), h);
}

}  // namespace

uint64_t MaterialFingerprint(const Brdf& material) {
  std::vector<Vec3> w_i, w_o;
  // 64 pairs from a 4-D Halton-like lattice over the upper hemisphere (cos theta uniform).
  for (int k = 0; k < 64; ++k) {
    const double a = (k + 0.5) / 64, b = std::fmod(k * 0.6180339887498949, 1.0);
    const double c = std::fmod(k * 0.7548776662466927, 1.0), d = std::fmod(k * 0.5698402909980532, 1.0);
    w_i.push_back(Direction(std::acos(1 - 0.98 * a), 2 * M_PI * b));
    w_o.push_back(Direction(std::acos(1 - 0.98 * c), 2 * M_PI * d));
  }
  // 32 mirror and near-mirror pairs, from the normal to grazing (glossy peaks).
  for (int k = 0; k < 32; ++k) {
    const double theta = (k % 16 + 0.5) / 16 * 1.5, phi = 0.37 * k;
    const double offset = k < 16 ? 0.0 : 0.02;
    w_o.push_back(Direction(theta, phi));
    w_i.push_back(Direction(theta + offset, phi + M_PI));
  }
  std::vector<Rgb> f(w_i.size());
  material.EvalBatch(w_i, w_o, f);
  uint64_t h = Fnv1a64(material.Spec());
  for (const Rgb& v : f) {
    for (int c = 0; c < 3; ++c) h = Mix(h, v[c]);
  }
  for (size_t k = 0; k < w_i.size(); k += 8) {
    h = Mix(h, material.GlossyProbability(w_o[k]));
    if (material.GlossyProbability(w_o[k]) > 0) h = Mix(h, material.GlossyPdf(w_o[k], w_i[k]));
  }
  const bool delta = material.IsDelta();
  h = Mix(h, delta);
  if (delta) {
    for (size_t k = 64; k < w_o.size(); k += 4) {
      const BrdfSample s = material.Sample(w_o[k], 0.5, 0.5, 0.5);
      h = Mix(h, s.w_i.x);
      h = Mix(h, s.w_i.y);
      h = Mix(h, s.w_i.z);
      for (int c = 0; c < 3; ++c) h = Mix(h, s.delta_reflectance[c]);
    }
  }
  return h;
}

std::string MaterialCacheKey(const Brdf& material) {
  char hex[24];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(MaterialFingerprint(material)));
  return material.Spec() + " #" + hex;
}

}  // namespace zbrdf
