// Cost of the fits (docs/fitting.md): one D-BRDF fit at order 10 on the thesis zone from scratch
// (quadrature, table projection, initial scan, Ceres, covariance) -- the target is <= 2 s on two
// cores --, the same with the precomputation reused (what fit-all pays per material), its parts,
// a GGX fit, and the error metric. The data are a GGX material's zonal tensor with 1% noise,
// made once outside the timed region.
#include <benchmark/benchmark.h>

#include "bench/fitting/bench_data.h"

#include <array>
#include <random>

#include "brdf/ggx.h"
#include "fitting/analytic_fit.h"
#include "fitting/dbrdf_fit.h"
#include "fitting/fit_error.h"
#include "fitting/fit_quadrature.h"

namespace zbrdf {
namespace {

using bench::ThesisZone;
const ZonalTensor& Data(int order) { return bench::NoisyGgxTensor(order); }

void BM_DBrdfFitFromScratch(benchmark::State& state) {
  const ZonalTensor& data = Data(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const DBrdfFitResult r = FitDBrdf(data);
    benchmark::DoNotOptimize(r.params.c);
    state.counters["chi2_per_dof"] = r.statistics.chi2_per_dof;
    state.counters["iterations"] = r.statistics.iterations;
  }
}
BENCHMARK(BM_DBrdfFitFromScratch)->Arg(8)->Arg(10)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_DBrdfFitReusingPrecomputation(benchmark::State& state) {
  const ZonalTensor& data = Data(static_cast<int>(state.range(0)));
  const DBrdfFitter fitter(data.zone(), data.order);
  for (auto _ : state) benchmark::DoNotOptimize(fitter.Fit(data).params.c);
}
BENCHMARK(BM_DBrdfFitReusingPrecomputation)->Arg(8)->Arg(10)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PairQuadrature(benchmark::State& state) {
  for (auto _ : state) {
    const PairQuadrature q(ThesisZone(), static_cast<int>(state.range(0)));
    benchmark::DoNotOptimize(q.size());
    state.counters["nodes"] = static_cast<double>(q.size());
  }
}
BENCHMARK(BM_PairQuadrature)->Arg(10)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_DBrdfTableProjection(benchmark::State& state) {
  const PairQuadrature q(ThesisZone(), static_cast<int>(state.range(0)));
  const int phi = static_cast<int>(state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(ProjectDBrdfTable(q, phi == 1 ? 91 : 46, phi).normal.data());
}
BENCHMARK(BM_DBrdfTableProjection)->Args({10, 1})->Args({8, 8})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GgxFit(benchmark::State& state) {
  const ZonalTensor& data = Data(static_cast<int>(state.range(0)));
  const AnalyticFitter fitter(data.zone(), data.order);
  for (auto _ : state) benchmark::DoNotOptimize(fitter.Fit(data, AnalyticModel::kGgx).shape);
}
BENCHMARK(BM_GgxFit)->Arg(8)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_CompareBrdfs(benchmark::State& state) {
  const GgxBrdf a(0.15, 0.15, Rgb(0.3), Rgb(0.1)), b(0.17, 0.17, Rgb(0.3), Rgb(0.1));
  for (auto _ : state) benchmark::DoNotOptimize(CompareBrdfs(a, b, ThesisZone()).cosine_l2);
}
BENCHMARK(BM_CompareBrdfs)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace zbrdf
