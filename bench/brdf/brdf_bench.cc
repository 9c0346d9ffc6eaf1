// Throughput of BRDF evaluation and sampling over 1e6 random direction pairs: Eval one pair at
// a time (a virtual call each) and EvalBatch over all pairs, for an analytic model (GGX) and a
// measured-material network (merl:chrome, which also has the proxy sampler). The counter
// "per_pair" is the wall time per pair.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "brdf/brdf.h"
#include "brdf/material_spec.h"

namespace zbrdf {
namespace {

constexpr size_t kPairs = 1'000'000;

struct Pairs {
  std::vector<Vec3> w_i, w_o;
  std::vector<double> u;  // 3 uniforms per pair, for sampling
};

Vec3 UniformUpper(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double z = 1.0 - uniform(rng), phi = 2.0 * M_PI * uniform(rng);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

const Pairs& RandomPairs() {
  static const Pairs pairs = [] {
    Pairs p;
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    p.w_i.resize(kPairs);
    p.w_o.resize(kPairs);
    p.u.resize(3 * kPairs);
    for (size_t k = 0; k < kPairs; ++k) {
      p.w_i[k] = UniformUpper(rng);
      p.w_o[k] = UniformUpper(rng);
    }
    for (double& u : p.u) u = std::min(uniform(rng), 0x1.fffffffffffffp-1);
    return p;
  }();
  return pairs;
}

void SetPerPair(benchmark::State& state) {
  state.counters["per_pair"] = benchmark::Counter(
      static_cast<double>(kPairs),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_Eval(benchmark::State& state, const char* spec) {
  const std::unique_ptr<Brdf> brdf = MakeBrdf(spec);
  const Pairs& pairs = RandomPairs();
  for (auto _ : state) {
    Rgb sum;
    for (size_t k = 0; k < kPairs; ++k) sum += brdf->Eval(pairs.w_i[k], pairs.w_o[k]);
    benchmark::DoNotOptimize(sum);
  }
  SetPerPair(state);
}

// single_precision: EvalBatchSinglePrecision, the simulator's evaluation.
void BM_EvalBatch(benchmark::State& state, const char* spec, bool single_precision = false) {
  const std::unique_ptr<Brdf> brdf = MakeBrdf(spec);
  const Pairs& pairs = RandomPairs();
  std::vector<Rgb> f(kPairs);
  for (auto _ : state) {
    if (single_precision) {
      brdf->EvalBatchSinglePrecision(pairs.w_i, pairs.w_o, f);
    } else {
      brdf->EvalBatch(pairs.w_i, pairs.w_o, f);
    }
    benchmark::DoNotOptimize(f.data());
    benchmark::ClobberMemory();
  }
  SetPerPair(state);
}

// One channel in single precision: what the transport build evaluates per sample (the pixel's
// Bayer channel).
void BM_EvalChannelBatch(benchmark::State& state, const char* spec) {
  const std::unique_ptr<Brdf> brdf = MakeBrdf(spec);
  const Pairs& pairs = RandomPairs();
  std::vector<double> value(kPairs);
  for (auto _ : state) {
    brdf->EvalChannelBatchSinglePrecision(pairs.w_i, pairs.w_o, 1, value);
    benchmark::DoNotOptimize(value.data());
    benchmark::ClobberMemory();
  }
  SetPerPair(state);
}

// Sample() then Eval() at the sample: what a path tracer or the simulator pays per bounce.
void BM_SampleAndEval(benchmark::State& state, const char* spec) {
  const std::unique_ptr<Brdf> brdf = MakeBrdf(spec);
  const Pairs& pairs = RandomPairs();
  for (auto _ : state) {
    Rgb sum;
    for (size_t k = 0; k < kPairs; ++k) {
      const BrdfSample s =
          brdf->Sample(pairs.w_o[k], pairs.u[3 * k], pairs.u[3 * k + 1], pairs.u[3 * k + 2]);
      if (s.pdf > 0) sum += brdf->Eval(s.w_i, pairs.w_o[k]) * (1.0 / s.pdf);
    }
    benchmark::DoNotOptimize(sum);
  }
  SetPerPair(state);
}

BENCHMARK_CAPTURE(BM_Eval, ggx, "ggx:alpha_x=0.2,alpha_y=0.3,F0=0.04,kd=0.1")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EvalBatch, ggx, "ggx:alpha_x=0.2,alpha_y=0.3,F0=0.04,kd=0.1")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Eval, nbrdf_chrome, "merl:chrome")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EvalBatch, nbrdf_chrome, "merl:chrome")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EvalBatch, nbrdf_chrome_single_precision, "merl:chrome", true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EvalChannelBatch, nbrdf_chrome, "merl:chrome")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SampleAndEval, ggx, "ggx:alpha_x=0.2,alpha_y=0.3,F0=0.04,kd=0.1")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SampleAndEval, nbrdf_chrome, "merl:chrome")->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace zbrdf
