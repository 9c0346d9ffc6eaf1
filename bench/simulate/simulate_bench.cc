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
  Pattern Uniform(uint16_t level) const {
    Pattern p;
    p.width = rig.projector.lens.width;
    p.height = rig.projector.lens.height;
    p.bit_depth = rig.projector.bit_depth;
    p.levels.assign(static_cast<size_t>(p.width) * p.height, level);
    return p;
  }
  Rig rig;
  OpticalSystem optics;
  RigMaps maps;
  std::unique_ptr<Brdf> material;
};

// Arguments: preset (0 fast, 1 full) and the rows integrated (ForwardModelOptions::row_stride;
// 8: every 8th row, a full-resolution build in about 2 s, for comparing two builds of the code
// by many alternating runs on a machine whose speed drifts).
void BM_TransportBuild(benchmark::State& state) {
  const Setup setup(state.range(0) ? Preset::kFull : Preset::kFast);
  ForwardModelOptions options;
  options.row_stride = static_cast<int>(state.range(1));
  for (auto _ : state) {
    const ForwardModel model(setup.optics, setup.maps, *setup.material, options);
    benchmark::DoNotOptimize(model.transport_entries());
  }
}
BENCHMARK(BM_TransportBuild)
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({1, 8})
    ->ArgNames({"full", "row_stride"})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

// One frame: the sparse product for a new pattern, then the sensor model.
void BM_Frame(benchmark::State& state) {
  const Setup setup(state.range(0) ? Preset::kFull : Preset::kFast);
  const ForwardModel model(setup.optics, setup.maps, *setup.material);
  const Pattern pattern = setup.Uniform(128);
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
// compute the true coefficients (on their own thread from the plan on, as zbrdf simulate), with the
// cache folder empty (cold: the first run on a machine) or filled by an untimed run (warm: every
// later capture, order or session of the same rig, material and seed). Counters: wall_s, rig_s (the
// virtual rig's clock: what the real rig takes), ratio = wall_s / rig_s (the issue asks <= 0.25 at
// full resolution), ready_s (zonal.exr on disk after the last frame, <= 1 s asked) and
// coef_error_pct (the coefficient error in the zone against the true coefficients, as zbrdf
// simulate reports it). Arguments: preset (0 fast, 1 full), cache (0 cold, 1 warm), samples per
// pixel (0: the rig's; zbrdf simulate --samples-per-pixel).
void BM_SimulatedSession(benchmark::State& state) {
  namespace fs = std::filesystem;
  const bool full = state.range(0) != 0, warm = state.range(1) != 0;
  const int samples = static_cast<int>(state.range(2));
  const std::string root =
      fs::temp_directory_path().string() + "/zbrdf-bench-session-" + std::to_string(::getpid());
  const std::string cache = root + "/cache";
  ::setenv("ZBRDF_CACHE_DIR", cache.c_str(), 1);
  Rig rig =
      ApplyPreset(LoadRig(DataPath("rig/rigs/thesis.yaml")), full ? Preset::kFull : Preset::kFast);
  if (samples > 0) rig.simulation.samples_per_pixel = samples;
  int run = 0;
  auto simulate = [&]() {
    VirtualCaptureArgs args;
    args.rig = rig;
    args.preset_name = full ? "full" : "fast";
    args.material_spec = "merl:blue-acrylic";
    args.job.out_dir = root + "/session-" + std::to_string(run++);
    args.job.order = 4;
    // As zbrdf simulate does: the true coefficients on a thread of their own from the plan on.
    EarlyTruth truth_job(GroundTruthOptions(), cache + "/truth");
    truth_job.StartAtPlan(&args);
    const VirtualCaptureOutcome out = RunVirtualCapture(args);
    const GroundTruth truth = truth_job.Get(*out.material, out.result.zonal);
    fs::remove_all(args.job.out_dir);
    return std::make_pair(out, CoefficientError(out.result.zonal, truth));
  };
  fs::remove_all(root);
  if (warm) simulate();
  double wall = 0, rig_s = 0, ready = 0, error = 0;
  for (auto _ : state) {
    state.PauseTiming();
    if (!warm) fs::remove_all(cache);
    state.ResumeTiming();
    const auto start = std::chrono::steady_clock::now();
    const auto [out, coefficient_error] = simulate();
    wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    rig_s = out.device_time_s;
    ready = out.result.ready_after_last_frame_s;
    error = coefficient_error;
  }
  fs::remove_all(root);
  ::unsetenv("ZBRDF_CACHE_DIR");
  state.counters["wall_s"] = wall;
  state.counters["rig_s"] = rig_s;
  state.counters["ratio"] = wall / rig_s;
  state.counters["ready_s"] = ready;
  state.counters["coef_error_pct"] = 100 * error;
}
BENCHMARK(BM_SimulatedSession)
    ->ArgsProduct({{0, 1}, {0, 1}, {0}})
    ->Args({1, 0, 256})  // the full preset's speed target at half its samples (docs/bench.md)
    ->ArgNames({"full", "warm", "samples"})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
}  // namespace zbrdf

namespace zbrdf {
namespace {

// Where the transport's Monte Carlo error comes from (docs/simulator.md, "Where the transport's
// error comes from"): frames of the fast preset at `samples` per pixel (seed 5) against 16x the
// samples (seed 6), every 12th camera row, under a uniform white pattern; relative RMS over the
// valid pixels of the whole frame (error_pct, the convergence test's measure), of the zone
// strategy's part (zone_pct) and of the glossy lobe strategy's part (lobe_pct), each part
// relative to the whole frame; and the share of the glossy sampler's draws that give no
// direction or one below the horizon or outside the lit zone (lobe_wasted). Arguments: material (0
// merl:blue-acrylic, 1 ggx:alpha=0.05,F0=0.04,kd=0.1, 2 merl:gold-metallic-paint, 3
// merl:white-paint), samples.
void BM_TransportConvergence(benchmark::State& state) {
  static const char* const kMaterials[] = {"merl:blue-acrylic", "ggx:alpha=0.05,F0=0.04,kd=0.1",
                                           "merl:gold-metallic-paint", "merl:white-paint"};
  const Setup setup(Preset::kFast);
  const auto material = MakeBrdf(kMaterials[state.range(0)]);
  using Strategies = ForwardModelOptions::Strategies;
  const Pattern white = setup.Uniform(255);
  // The zone and lobe parts of a transport's frame (the control variate's exact part, the same
  // for every seed, taken out of both), and its sample counts.
  struct Parts {
    std::vector<float> zone, lobe;
    ForwardModel::SampleCounts counts;
  };
  auto parts = [&](int samples, uint64_t seed, const std::vector<float>& control) {
    Rig rig = setup.rig;
    rig.simulation.samples_per_pixel = samples;
    const OpticalSystem optics(rig);
    Parts out;
    for (Strategies s : {Strategies::kZoneOnly, Strategies::kLobeOnly}) {
      ForwardModelOptions options;
      options.seed = seed;
      options.row_stride = 12;
      options.strategies = s;
      const ForwardModel model(optics, setup.maps, *material, options);
      std::vector<float> rate = model.ElectronRate(white);
      for (size_t i = 0; i < rate.size(); ++i) rate[i] -= control[i];
      (s == Strategies::kZoneOnly ? out.zone : out.lobe) = std::move(rate);
      out.counts = model.sample_counts();
    }
    return out;
  };
  const int samples = static_cast<int>(state.range(1));
  std::vector<float> control;
  {
    ForwardModelOptions options;
    options.row_stride = 12;
    options.strategies = Strategies::kControlOnly;
    control = ForwardModel(setup.optics, setup.maps, *material, options).ElectronRate(white);
  }
  const Parts reference = parts(16 * samples, 6, control);
  double error = 0, zone = 0, lobe = 0, wasted = 0;
  for (auto _ : state) {
    const Parts estimate = parts(samples, 5, control);
    double num = 0, num_zone = 0, num_lobe = 0, den = 0;
    for (size_t i = 0; i < control.size(); ++i) {
      const int y = static_cast<int>(i) / setup.rig.camera.width;
      if (y % 12 != 0 || !setup.maps.camera.Valid(static_cast<int>(i))) continue;
      const double dz = double(estimate.zone[i]) - reference.zone[i];
      const double dl = double(estimate.lobe[i]) - reference.lobe[i];
      const double whole = double(reference.zone[i]) + reference.lobe[i] + control[i];
      num += (dz + dl) * (dz + dl);
      num_zone += dz * dz;
      num_lobe += dl * dl;
      den += whole * whole;
    }
    error = 100 * std::sqrt(num / den);
    zone = 100 * std::sqrt(num_zone / den);
    lobe = 100 * std::sqrt(num_lobe / den);
    const auto& c = estimate.counts;
    wasted =
        c.lobe > 0 ? double(c.lobe_no_sample + c.lobe_below_horizon + c.lobe_unlit) / c.lobe : 0.0;
  }
  state.SetLabel(kMaterials[state.range(0)]);
  state.counters["error_pct"] = error;
  state.counters["zone_pct"] = zone;
  state.counters["lobe_pct"] = lobe;
  state.counters["lobe_wasted"] = wasted;
}
BENCHMARK(BM_TransportConvergence)
    ->ArgsProduct({{0, 1, 2, 3}, {256, 512, 1024}})
    ->ArgNames({"material", "samples"})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
}  // namespace zbrdf
