// Evaluation speed of the sphere functions. Report: ns per direction for all Z_lm at L = 10.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "basis/legendre.h"
#include "basis/spherical_harmonics.h"
#include "basis/zonal_basis.h"

namespace zbrdf {
namespace {

std::vector<Vec3> Directions(int n) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> out(n);
  for (Vec3& w : out) {
    const double z = std::cos(DegToRad(9)) - u(rng) * (std::cos(DegToRad(9)) - std::cos(DegToRad(57)));
    const double phi = 2 * M_PI * u(rng), r = std::sqrt(1 - z * z);
    w = {r * std::cos(phi), r * std::sin(phi), z};
  }
  return out;
}

// All Z_lm (L = state.range(0)) at 1e6 directions in the zone [9, 57] deg; items = directions.
void BM_ZonalBasisAll(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  const ZonalBasis zb(Zone::FromDegrees(9, 57), order);
  const std::vector<Vec3> dirs = Directions(1000000);
  std::vector<double> out(zb.size());
  for (auto _ : state) {
    double sink = 0;
    for (const Vec3& w : dirs) {
      zb.Eval(w, out.data());
      sink += out[zb.size() - 1];
    }
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(state.iterations() * dirs.size());
  state.counters["ns_per_direction"] = benchmark::Counter(
      static_cast<double>(dirs.size()), benchmark::Counter::kIsIterationInvariantRate |
                                            benchmark::Counter::kInvert);
}
BENCHMARK(BM_ZonalBasisAll)->Arg(4)->Arg(10)->Unit(benchmark::kMillisecond);

void BM_ShAll(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  const std::vector<Vec3> dirs = Directions(1000000);
  std::vector<double> out(ShCount(order));
  for (auto _ : state) {
    double sink = 0;
    for (const Vec3& w : dirs) {
      EvalShAll(order, w, out.data());
      sink += out.back();
    }
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(state.iterations() * dirs.size());
  state.counters["ns_per_direction"] = benchmark::Counter(
      static_cast<double>(dirs.size()), benchmark::Counter::kIsIterationInvariantRate |
                                            benchmark::Counter::kInvert);
}
BENCHMARK(BM_ShAll)->Arg(10)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace zbrdf
