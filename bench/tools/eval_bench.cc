// `zbrdf eval` on 1e6 direction pairs: parse the text, evaluate, format the CSV (what the command
// does between reading its input and writing its output), on all worker threads
// ($ZBRDF_THREADS, default: every core). Models: an analytic GGX and a measured network
// (merl:blue-acrylic). The counters give the time per pair; the acceptance target is 1e6 pairs
// in under 2 s for the analytic model on 2 cores. Also the stages alone, to see where time goes.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "brdf/material_spec.h"
#include "tools/brdf_eval.h"

namespace zbrdf {
namespace {

constexpr int kPairs = 1'000'000;

// 1e6 lines "theta_i phi_i theta_o phi_o" with %.17g numbers, fixed seed.
const std::string& PairsText() {
  static const std::string text = [] {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> theta(0.0, 0.5 * M_PI), phi(0.0, 2 * M_PI);
    std::string t;
    t.reserve(static_cast<size_t>(kPairs) * 90);
    char line[128];
    for (int k = 0; k < kPairs; ++k) {
      std::snprintf(line, sizeof(line), "%.17g %.17g %.17g %.17g\n", theta(rng), phi(rng),
                    theta(rng), phi(rng));
      t += line;
    }
    return t;
  }();
  return text;
}

void RunEndToEnd(benchmark::State& state, const char* spec) {
  const auto brdf = MakeBrdf(spec);
  const std::string& text = PairsText();
  size_t bytes = 0;
  for (auto _ : state) {
    const std::vector<DirectionPair> pairs = ParseDirectionPairs(text, "bench");
    const std::vector<Rgb> f = EvaluatePairs(*brdf, pairs);
    const std::string out = FormatEvaluations(pairs, f, EvalFormat::kCsv, spec, spec);
    bytes = out.size();
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["pairs"] = kPairs;
  state.counters["output_MB"] = bytes / 1e6;
  state.counters["per_pair"] = benchmark::Counter(
      static_cast<double>(kPairs),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_EvalEndToEndGgx(benchmark::State& state) {
  RunEndToEnd(state, "ggx:alpha=0.2,F0=0.9,kd=0.05");
}
void BM_EvalEndToEndNetwork(benchmark::State& state) { RunEndToEnd(state, "merl:blue-acrylic"); }

void BM_ParseOnly(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(ParseDirectionPairs(PairsText(), "bench").data());
}

void BM_FormatOnly(benchmark::State& state) {
  const std::vector<DirectionPair> pairs = ParseDirectionPairs(PairsText(), "bench");
  const std::vector<Rgb> f(pairs.size(), Rgb(0.123456789, 1.5, 2e-7));
  for (auto _ : state) {
    benchmark::DoNotOptimize(FormatEvaluations(pairs, f, EvalFormat::kCsv, "", "").data());
  }
}

BENCHMARK(BM_EvalEndToEndGgx)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_EvalEndToEndNetwork)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_ParseOnly)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_FormatOnly)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace
}  // namespace zbrdf
