// Simulator speed: transport build and frames for the thesis rig, at both presets.
// Report: seconds per full-resolution frame for a measured-material network, and a 150-frame
// capture's worth of frames at the fast preset.
#include <benchmark/benchmark.h>

#include <memory>

#include "basis/data_path.h"
#include "brdf/material_spec.h"
#include "simulate/imaging.h"

namespace zbrdf {
namespace {

struct Setup {
  explicit Setup(Preset preset)
      : rig(ApplyPreset(LoadRig(DataPath("rig/rigs/thesis.yaml")), preset)),
        optics(rig),
        maps(LoadOrBuildRigMaps(optics, DefaultCacheDir())),
        material(MakeBrdf("merl:blue-acrylic")) {}
  Pattern Gray() const {
    Pattern p;
    p.width = rig.projector.lens.width;
    p.height = rig.projector.lens.height;
    p.bit_depth = rig.projector.bit_depth;
    p.levels.assign(static_cast<size_t>(p.width) * p.height, 128);
    return p;
  }
  Rig rig;
  OpticalSystem optics;
  RigMaps maps;
  std::unique_ptr<Brdf> material;
};

void BM_TransportBuild(benchmark::State& state) {
  const Setup setup(state.range(0) ? Preset::kFull : Preset::kFast);
  for (auto _ : state) {
    const ForwardModel model(setup.optics, setup.maps, *setup.material);
    benchmark::DoNotOptimize(model.transport_entries());
  }
}
BENCHMARK(BM_TransportBuild)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->Iterations(1);

// One frame: the sparse product for a new pattern, then the sensor model.
void BM_Frame(benchmark::State& state) {
  const Setup setup(state.range(0) ? Preset::kFull : Preset::kFast);
  const ForwardModel model(setup.optics, setup.maps, *setup.material);
  const Pattern pattern = setup.Gray();
  uint64_t key = 0;
  for (auto _ : state) {
    const Frame frame = model.Render(pattern, 10000, ++key, true);
    benchmark::DoNotOptimize(frame.data.data());
  }
}
BENCHMARK(BM_Frame)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace zbrdf
