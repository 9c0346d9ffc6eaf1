// Simulator speed: transport build and frames for the thesis rig, at both presets, and whole
// simulated sessions against the rig time they stand for (docs/bench.md, "Simulator speed").
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <vector>

#include "acquisition/ground_truth.h"
#include "basis/data_path.h"
#include "brdf/material_spec.h"
#include "simulate/imaging.h"
#include "simulate/sensor_pixels.h"
#include "tools/virtual_capture.h"

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

// The sensor model alone on a frame of the thesis rig's sensor at full resolution (one thread):
// a disk of a fifth of the pixels lit from a few electrons to the full well at a 1 s exposure,
// the rest off the sample (rate 0), as the sample's image lies in a frame. Argument: 0 the
// scalar path, 1 the one the CPU gets (AVX2 if it has it).
void BM_SensorModel(benchmark::State& state) {
  const Rig rig = LoadRig(DataPath("rig/rigs/thesis.yaml"));
  const SensorParams& sensor = rig.sensor;
  const int width = rig.camera.width, height = rig.camera.height;
  const double radius_squared = 0.2 * width * height / M_PI;
  std::vector<float> rate(static_cast<size_t>(width) * height, 0.0f);
  uint64_t word = 1;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      word = HashMix(word);
      const double dx = x - 0.5 * width, dy = y - 0.5 * height;
      if (dx * dx + dy * dy > radius_squared) continue;
      rate[static_cast<size_t>(y) * width + x] =
          static_cast<float>(5 + sensor.full_well_e * UniformFromHash(word));
    }
  }
  SensorPixelModel model = SensorPixelModel::Of(sensor, 1.0);
  std::vector<uint16_t> counts(rate.size());
  for (auto _ : state) {
    model.key = HashMix(model.key);
    if (state.range(0)) {
      RenderSensorPixels(rate, 0, model, counts.data());
    } else {
      RenderSensorPixelsScalar(rate, 0, model, counts.data());
    }
    benchmark::DoNotOptimize(counts.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(rate.size()));
}
BENCHMARK(BM_SensorModel)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace zbrdf

namespace zbrdf {
namespace {

// A whole `zbrdf simulate` of merl:blue-acrylic at order 4 (issue "faster than the rig"): build
// or load the rig's maps and the light transport, meter, capture and process every frame, and
// compute the true coefficients, with the cache folder empty (cold: the first run on a machine)
// or filled by an untimed run (warm: every later capture, order or session of the same rig,
// material and seed). Counters: wall_s, rig_s (the virtual rig's clock: what the real rig
// takes), ratio = wall_s / rig_s (the issue asks <= 0.25 at full resolution), and
// ready_s (zonal.exr on disk after the last frame, <= 1 s asked).
// Arguments: preset (0 fast, 1 full), cache (0 cold, 1 warm).
void BM_SimulatedSession(benchmark::State& state) {
  namespace fs = std::filesystem;
  const bool full = state.range(0) != 0, warm = state.range(1) != 0;
  const std::string root = fs::temp_directory_path().string() + "/zbrdf-bench-session-" +
                           std::to_string(::getpid());
  const std::string cache = root + "/cache";
  ::setenv("ZBRDF_CACHE_DIR", cache.c_str(), 1);
  const Rig rig =
      ApplyPreset(LoadRig(DataPath("rig/rigs/thesis.yaml")), full ? Preset::kFull : Preset::kFast);
  int run = 0;
  auto simulate = [&]() {
    VirtualCaptureArgs args;
    args.rig = rig;
    args.preset_name = full ? "full" : "fast";
    args.material_spec = "merl:blue-acrylic";
    args.job.out_dir = root + "/session-" + std::to_string(run++);
    args.job.order = 4;
    const VirtualCaptureOutcome out = RunVirtualCapture(args);
    const GroundTruth truth = TrueZonalCoefficientsCached(*out.material, out.result.zonal,
                                                          GroundTruthOptions(), cache + "/truth");
    benchmark::DoNotOptimize(truth.value.data());
    fs::remove_all(args.job.out_dir);
    return out;
  };
  fs::remove_all(root);
  if (warm) simulate();
  double wall = 0, rig_s = 0, ready = 0;
  for (auto _ : state) {
    state.PauseTiming();
    if (!warm) fs::remove_all(cache);
    state.ResumeTiming();
    const auto start = std::chrono::steady_clock::now();
    const VirtualCaptureOutcome out = simulate();
    wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    rig_s = out.device_time_s;
    ready = out.result.ready_after_last_frame_s;
  }
  fs::remove_all(root);
  ::unsetenv("ZBRDF_CACHE_DIR");
  state.counters["wall_s"] = wall;
  state.counters["rig_s"] = rig_s;
  state.counters["ratio"] = wall / rig_s;
  state.counters["ready_s"] = ready;
}
BENCHMARK(BM_SimulatedSession)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->ArgNames({"full", "warm"})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
}  // namespace zbrdf
