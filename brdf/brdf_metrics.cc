#include "brdf/brdf_metrics.h"

#include <cmath>
#include <mutex>
#include <random>
#include <vector>

#include "basis/error.h"
#include "basis/parallel.h"

namespace zbrdf {
namespace {

struct Sums {
  double diff[3] = {0, 0, 0}, diff2[3] = {0, 0, 0};  // of the estimator and its square
  double ref[3] = {0, 0, 0};
};

Vec3 UniformHemisphere(double u0, double u1) {
  const double z = 1.0 - u0;
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = 2.0 * M_PI * u1;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace

double BrdfDistance::RelativeMean() const {
  double sum = 0;
  for (int c = 0; c < 3; ++c) sum += reference_norm[c] > 0 ? l2[c] / reference_norm[c] : 0.0;
  return sum / 3.0;
}

nlohmann::json BrdfDistance::ToJson() const {
  return {{"definition",
           "sqrt(1/(2 pi)^2 integral integral (f_a - f_b)^2 cos^2(theta_i) dw_i dw_o), per "
           "channel (Ngan et al. 2005)"},
          {"l2_per_sr", {l2.r, l2.g, l2.b}},
          {"l2_standard_error", {l2_standard_error.r, l2_standard_error.g, l2_standard_error.b}},
          {"reference_norm_per_sr", {reference_norm.r, reference_norm.g, reference_norm.b}},
          {"l2_mean", Mean()},
          {"relative_mean", RelativeMean()}};
}

BrdfDistance CosineWeightedL2(const Brdf& a, const Brdf& b, int64_t samples, uint64_t seed) {
  if (samples < 16) throw InputError("CosineWeightedL2: at least 16 samples are needed");
  constexpr int64_t kChunk = 4096;
  const int64_t chunks = (samples + kChunk - 1) / kChunk;
  // Delta materials have no density to mix in: their samples would be point masses.
  std::vector<const Brdf*> samplers;
  if (!a.IsDelta()) samplers.push_back(&a);
  if (!b.IsDelta()) samplers.push_back(&b);
  const int strategies = static_cast<int>(samplers.size()) + 1;
  Sums total;
  std::mutex mutex;
  ParallelFor(chunks, 1, [&](int64_t begin, int64_t end) {
    Sums local;
    for (int64_t chunk = begin; chunk < end; ++chunk) {
      std::mt19937_64 rng(seed * 1000003 + static_cast<uint64_t>(chunk));
      auto uniform = [&]() { return static_cast<double>(rng() >> 11) * 0x1p-53; };
      const int64_t n = std::min(kChunk, samples - chunk * kChunk);
      for (int64_t k = 0; k < n; ++k) {
        const Vec3 w_o = UniformHemisphere(uniform(), uniform());
        const double pick = uniform(), u0 = uniform(), u1 = uniform(), u2 = uniform();
        const int strategy = std::min(strategies - 1, static_cast<int>(pick * strategies));
        Vec3 w_i;
        if (strategy < static_cast<int>(samplers.size())) {
          w_i = samplers[strategy]->Sample(w_o, u0, u1, u2).w_i;
        } else {
          w_i = UniformHemisphere(u1, u2);
        }
        const double length = Length(w_i);
        if (!(length > 0) || w_i.z <= 0) continue;  // contributes 0 (f = 0 below the horizon)
        w_i = w_i / length;
        double q = 1.0 / (2.0 * M_PI);
        for (const Brdf* sampler : samplers) q += sampler->Pdf(w_o, w_i);
        q /= strategies;
        // Estimator of (1 / (2 pi)^2) integral integral g: g / (q p_o) / (2 pi)^2 with
        // p_o = 1 / (2 pi), i.e. g / (q 2 pi).
        const Rgb fa = a.Eval(w_i, w_o), fb = b.Eval(w_i, w_o);
        const double weight = w_i.z * w_i.z / (q * 2.0 * M_PI);
        for (int c = 0; c < 3; ++c) {
          const double d = (fa[c] - fb[c]) * (fa[c] - fb[c]) * weight;
          local.diff[c] += d;
          local.diff2[c] += d * d;
          local.ref[c] += fa[c] * fa[c] * weight;
        }
      }
    }
    std::lock_guard<std::mutex> lock(mutex);
    for (int c = 0; c < 3; ++c) {
      total.diff[c] += local.diff[c];
      total.diff2[c] += local.diff2[c];
      total.ref[c] += local.ref[c];
    }
  });
  BrdfDistance result;
  const double n = static_cast<double>(samples);
  for (int c = 0; c < 3; ++c) {
    const double mean = total.diff[c] / n;
    const double variance = std::max(0.0, total.diff2[c] / n - mean * mean) / n;
    result.l2[c] = std::sqrt(mean);
    // d sqrt(m) = dm / (2 sqrt(m)).
    result.l2_standard_error[c] = mean > 0 ? std::sqrt(variance) / (2.0 * std::sqrt(mean)) : 0.0;
    result.reference_norm[c] = std::sqrt(total.ref[c] / n);
  }
  return result;
}

}  // namespace zbrdf
