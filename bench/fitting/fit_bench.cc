// Cost of the fits (docs/fitting.md): one D-BRDF fit at order 10 on the thesis zone from scratch
// (quadrature, table projection, initial scan, Ceres, covariance) -- the target is <= 2 s on two
// cores --, the same with the precomputation reused (what fit-all pays per material), its parts,
// a GGX fit, and the error metric. The data are a GGX material's zonal tensor with 1% noise,
// made once outside the timed region.
#include <benchmark/benchmark.h>

#include <array>
#include <random>

#include "brdf/ggx.h"
#include "fitting/analytic_fit.h"
#include "fitting/dbrdf_fit.h"
#include "fitting/fit_error.h"
#include "fitting/fit_quadrature.h"

namespace zbrdf {
namespace {

const Zone& ThesisZone() {
  static const Zone zone = Zone::FromDegrees(11.3, 54.9);  // the thesis rig at the fast preset
  return zone;
}

const ZonalTensor& Data(int order) {
  static std::array<std::unique_ptr<ZonalTensor>, 31> cache;
  if (!cache[order]) {
    const GgxBrdf ggx(0.15, 0.15, Rgb(0.3), Rgb(0.1, 0.2, 0.3));
    const PairQuadrature q(ThesisZone(), order);
    const auto iso = q.ProjectIsotropicBrdf(ggx);
    auto data = std::make_unique<ZonalTensor>();
    data->theta_min_rad = ThesisZone().theta_min_rad();
    data->theta_max_rad = ThesisZone().theta_max_rad();
    data->order = order;
    std::mt19937_64 rng(5);
    std::normal_distribution<double> normal;
    for (int ch = 0; ch < 3; ++ch) {
      data->z[ch] = IsotropicLayout(order).Expand(iso[ch]);
      const double sigma = 0.01 * std::sqrt(data->z[ch].squaredNorm() / data->z[ch].size());
      data->variance[ch] = Eigen::MatrixXd::Constant(data->z[ch].rows(), data->z[ch].cols(), sigma * sigma);
      for (Eigen::Index i = 0; i < data->z[ch].size(); ++i) data->z[ch].data()[i] += sigma * normal(rng);
    }
    cache[order] = std::move(data);
  }
  return *cache[order];
}

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
