// The simulated rig behind the drivers' Camera and Projector interfaces.
//
// A capture session runs against VirtualRig::camera() and ::projector() exactly as against
// hardware. The virtual camera renders the pattern the virtual projector shows (ForwardModel)
// and advances a modeled clock by what the real rig would spend (frame period, exposure,
// readout); the session's settle waits go through the same clock, so the wall time a real
// capture would take is the clock's reading at the end.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "brdf/brdf.h"
#include "drivers/camera.h"
#include "drivers/clock.h"
#include "drivers/projector.h"
#include "rig/direction_maps.h"
#include "rig/optics.h"
#include "rig/rig.h"
#include "simulate/imaging.h"

namespace zbrdf {

class VirtualRig;

class VirtualProjector final : public Projector {
 public:
  explicit VirtualProjector(const VirtualRig& rig) : rig_(rig) {}
  ProjectorInfo Info() const override;
  void Show(const Pattern& pattern) override;
  // Up to kRowProductPatterns announced patterns are kept; the camera renders them together
  // when the first of them is shown (ForwardModel::ElectronRates).
  int PatternsAhead() const override { return kRowProductPatterns; }
  void Upcoming(std::span<const Pattern> patterns) override;
  const Pattern& current() const { return current_; }
  uint64_t generation() const { return generation_; }
  const std::vector<Pattern>& upcoming() const { return upcoming_; }
  uint64_t upcoming_generation() const { return upcoming_generation_; }

 private:
  const VirtualRig& rig_;
  Pattern current_;
  uint64_t generation_ = 0;
  std::vector<Pattern> upcoming_;
  uint64_t upcoming_generation_ = 0;
};

class VirtualCamera final : public Camera {
 public:
  VirtualCamera(VirtualRig& rig) : rig_(rig) {}
  CameraInfo Info() const override;
  double SetExposure(double exposure_us) override;
  void SetTriggerMode(TriggerMode mode) override { mode_ = mode; }
  void SetNextFrameIndex(uint64_t index) override { next_index_ = index; }
  Frame Grab(std::chrono::milliseconds timeout) override;
  // Patterns rendered in windows announced ahead (VirtualProjector::Upcoming), and those of them
  // that were then shown: the difference is rendering the session did not need.
  uint64_t rates_rendered_ahead() const { return rates_rendered_ahead_; }
  uint64_t rates_from_windows() const { return rates_from_windows_; }

 private:
  VirtualRig& rig_;
  TriggerMode mode_ = TriggerMode::kSoftware;
  double exposure_us_ = 10000;
  uint64_t next_index_ = 0;
  uint64_t frame_id_ = 0;
  int64_t last_start_us_ = -1000000000;
  // The shown pattern's electron rate: the one announced ahead, else rendered alone.
  std::vector<float> RateOfShownPattern();

  // Electron rate of the last pattern rendered (exposure brackets reuse it).
  uint64_t cached_generation_ = ~0ull, cached_material_ = ~0ull;
  std::vector<float> cached_rate_;
  // Rates of announced patterns not yet shown, rendered in one pass, for one material.
  std::vector<std::pair<Pattern, std::vector<float>>> prepared_;
  uint64_t prepared_upcoming_ = 0, prepared_material_ = ~0ull;
  uint64_t rates_rendered_ahead_ = 0, rates_from_windows_ = 0;
};

class VirtualRig {
 public:
  struct Options {
    uint64_t seed = 1;
    bool noise = true;
    std::string cache_dir;  // direction maps, and transports under transport/; empty: DefaultCacheDir()
    bool transport_cache = true;  // reuse the light transport of the same rig, material and seed
    ProgressCallback progress;
  };

  // Traces the rig's maps (or loads them from the cache) and builds the material's transport.
  VirtualRig(const Rig& rig, std::shared_ptr<const Brdf> material, const Options& options);

  Camera& camera() { return camera_; }
  Projector& projector() { return projector_; }
  Clock& clock() { return clock_; }
  const Rig& rig() const { return optics_->rig(); }
  const OpticalSystem& optics() const { return *optics_; }
  const RigMaps& maps() const { return *maps_; }
  const ForwardModel& model() const { return *model_; }
  const Brdf& material() const { return *material_; }
  const Options& options() const { return options_; }
  const VirtualProjector& virtual_projector() const { return projector_; }
  // Counts material changes, so that cached renderings are dropped.
  uint64_t material_generation() const { return material_generation_; }

  // Swaps the sample (e.g. a calibration target), rebuilding the transport.
  void SetMaterial(std::shared_ptr<const Brdf> material);

 private:
  Options options_;
  std::unique_ptr<OpticalSystem> optics_;
  std::unique_ptr<RigMaps> maps_;
  std::shared_ptr<const Brdf> material_;
  std::unique_ptr<ForwardModel> model_;
  uint64_t material_generation_ = 0;
  ModelClock clock_;
  VirtualProjector projector_;
  VirtualCamera camera_;
};

}  // namespace zbrdf
