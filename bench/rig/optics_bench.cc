// Ray tracing through the rig's mirrors: a camera ray to the sample (the transport traces 16 per
// lit pixel), the dome's exit alone, and the direction maps a new rig traces before anything else
// (docs/simulator.md, "The rig's rays").
#include <benchmark/benchmark.h>

#include <vector>

#include "basis/data_path.h"
#include "rig/direction_maps.h"
#include "rig/optics.h"

namespace zbrdf {
namespace {

// Camera rays over the pixel and the lens aperture, for every 4th pixel of every 4th row of the
// full-resolution thesis camera (about 87000 rays; the fixed pattern makes runs comparable).
std::vector<Ray> CameraRays(const OpticalSystem& optics) {
  const ThinLens& camera = optics.camera();
  std::vector<Ray> rays;
  int k = 0;
  for (int y = 0; y < camera.params().height; y += 4) {
    for (int x = 0; x < camera.params().width; x += 4, ++k) {
      const double u0 = ((k * 7) % 16 + 0.5) / 16, u1 = ((k * 11) % 16 + 0.5) / 16;
      rays.push_back(camera.GenerateRay(x + 0.5, y + 0.5, u0, u1));
    }
  }
  return rays;
}

void BM_TraceToSample(benchmark::State& state) {
  const OpticalSystem optics(LoadRig(DataPath("rig/rigs/thesis.yaml")));
  const std::vector<Ray> rays = CameraRays(optics);
  int64_t landed = 0;
  for (auto _ : state) {
    for (const Ray& ray : rays) {
      const auto path = optics.TraceToSample(ray);
      landed += path.status == OpticalSystem::PathStatus::kLanded;
    }
  }
  benchmark::DoNotOptimize(landed);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(rays.size()));
}
BENCHMARK(BM_TraceToSample)->Unit(benchmark::kMillisecond);

// The dome's exit alone, for the camera rays reflected off the parabola (those the dome sees).
void BM_DomeIntersect(benchmark::State& state) {
  const OpticalSystem optics(LoadRig(DataPath("rig/rigs/thesis.yaml")));
  std::vector<Ray> reflected;
  for (const Ray& ray : CameraRays(optics)) {
    bool from_above = false;
    const auto hit = optics.parabola().Intersect(ray, 1e-7, &from_above);
    if (!hit || !from_above) continue;
    reflected.push_back({hit->point, Normalize(Reflect(ray.direction, hit->normal))});
  }
  double sum = 0;
  for (auto _ : state) {
    for (const Ray& ray : reflected) {
      const auto hit = optics.dome().Intersect(ray, 1e-7);
      if (hit) sum += hit->t;
    }
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(reflected.size()));
}
BENCHMARK(BM_DomeIntersect)->Unit(benchmark::kMillisecond);

// The rig's direction maps, traced without the cache: argument 0 the fast preset, 1 full
// resolution (what the first simulation of a rig spends before its transport).
void BM_RigMaps(benchmark::State& state) {
  const Rig rig = ApplyPreset(LoadRig(DataPath("rig/rigs/thesis.yaml")),
                              state.range(0) ? Preset::kFull : Preset::kFast);
  const OpticalSystem optics(rig);
  for (auto _ : state) {
    const RigMaps maps = BuildRigMaps(optics);
    benchmark::DoNotOptimize(maps.grid.xy.data());
  }
}
BENCHMARK(BM_RigMaps)
    ->ArgName("full")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace zbrdf
