// Cost of the prior fit (docs/prior.md), the target of issue 14: fitting a session with the
// default prior takes <= 2 s at order 8 on 2 cores. Parts: reading the shipped prior; projecting
// its grid on the zone (once per zone, order and prior, then cached on disk by `zbrdf fit`);
// the fit itself (NNLS, log-PCA second stage, 8 replicates for the uncertainty) with the
// projection given, which is what every later fit of a session at that zone and order pays;
// and everything from scratch. The data are a GGX material's zonal tensor with 1% noise, made
// once outside the timed region.
#include <benchmark/benchmark.h>

#include "bench/fitting/bench_data.h"

#include <array>
#include <memory>
#include <random>

#include "brdf/brdf_prior.h"
#include "brdf/ggx.h"
#include "fitting/fit_quadrature.h"
#include "fitting/prior_fit.h"

namespace zbrdf {
namespace {

const Zone& FastThesisZone() { return bench::ThesisZone(); }
const ZonalTensor& GgxData(int order) { return bench::NoisyGgxTensor(order); }

std::shared_ptr<const BrdfPrior> DefaultPrior() {
  static const auto prior = std::make_shared<const BrdfPrior>(ReadPriorFile(DefaultPriorPath()));
  return prior;
}

void BM_ReadDefaultPrior(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(ReadPriorFile(DefaultPriorPath()));
}
BENCHMARK(BM_ReadDefaultPrior)->Unit(benchmark::kMillisecond)->UseRealTime();

// The projection of the prior's grid on the zone and order (cached on disk by zbrdf fit).
void BM_PriorProjection(benchmark::State& state) {
  const auto prior = DefaultPrior();
  PriorFitOptions options;
  for (auto _ : state) {
    PriorFitter fitter(FastThesisZone(), static_cast<int>(state.range(0)), prior, options);
    benchmark::DoNotOptimize(fitter.AtomProjection().data());
  }
}
BENCHMARK(BM_PriorProjection)->Arg(8)->Unit(benchmark::kMillisecond)->UseRealTime();

// One fit with the projection given: NNLS, second stage and `replicates` refits.
void BM_PriorFitGivenProjection(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  PriorFitOptions options;
  options.replicates = static_cast<int>(state.range(1));
  const PriorFitter fitter(FastThesisZone(), order, DefaultPrior(), options);
  const ZonalTensor& data = GgxData(order);
  for (auto _ : state) benchmark::DoNotOptimize(fitter.Fit(data).brdf);
}
BENCHMARK(BM_PriorFitGivenProjection)
    ->Args({8, 8})
    ->Args({8, 0})
    ->Args({10, 8})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// What `zbrdf fit --model prior` pays once the projection is cached: read the prior, build the
// fitter from the cached projection (here: a copy in memory) and fit.
void BM_PriorFitSessionCached(benchmark::State& state) {
  const int order = 8;
  const Eigen::MatrixXf projection =
      PriorFitter(FastThesisZone(), order, DefaultPrior()).TableProjection();
  const ZonalTensor& data = GgxData(order);
  for (auto _ : state) {
    auto prior = std::make_shared<const BrdfPrior>(ReadPriorFile(DefaultPriorPath()));
    const PriorFitter fitter(FastThesisZone(), order, prior, {}, &projection);
    benchmark::DoNotOptimize(fitter.Fit(data).brdf);
  }
}
BENCHMARK(BM_PriorFitSessionCached)->Unit(benchmark::kMillisecond)->UseRealTime();

// The first fit at a new zone and order: read, project, fit.
void BM_PriorFitFromScratch(benchmark::State& state) {
  const int order = 8;
  const ZonalTensor& data = GgxData(order);
  for (auto _ : state) {
    auto prior = std::make_shared<const BrdfPrior>(ReadPriorFile(DefaultPriorPath()));
    const PriorFitter fitter(FastThesisZone(), order, prior);
    benchmark::DoNotOptimize(fitter.Fit(data).brdf);
  }
}
BENCHMARK(BM_PriorFitFromScratch)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace zbrdf
