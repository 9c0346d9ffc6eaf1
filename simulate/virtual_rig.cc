#include "simulate/virtual_rig.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "basis/error.h"

namespace zbrdf {

ProjectorInfo VirtualProjector::Info() const {
  const ProjectorParams& p = rig_.rig().projector;
  ProjectorInfo info;
  info.id = "virtual";
  info.model = "simulated projector (" + rig_.rig().name + ")";
  info.width = p.lens.width;
  info.height = p.lens.height;
  info.bit_depth = p.bit_depth;
  return info;
}

void VirtualProjector::Show(const Pattern& pattern) {
  const ProjectorInfo info = Info();
  if (pattern.width != info.width || pattern.height != info.height ||
      pattern.levels.size() != static_cast<size_t>(pattern.width) * pattern.height) {
    throw InputError("pattern is " + std::to_string(pattern.width) + "x" +
                     std::to_string(pattern.height) + " but the virtual projector is " +
                     std::to_string(info.width) + "x" + std::to_string(info.height));
  }
  if (pattern.bit_depth != info.bit_depth) {
    throw InputError("pattern has " + std::to_string(pattern.bit_depth) +
                     "-bit levels but the virtual projector takes " +
                     std::to_string(info.bit_depth));
  }
  current_ = pattern;
  ++generation_;
}

void VirtualProjector::Upcoming(std::span<const Pattern> patterns) {
  upcoming_.assign(patterns.begin(),
                   patterns.begin() + std::min<size_t>(patterns.size(), PatternsAhead()));
  ++upcoming_generation_;
}

namespace {

bool SamePattern(const Pattern& a, const Pattern& b) {
  return a.width == b.width && a.height == b.height && a.bit_depth == b.bit_depth &&
         a.levels == b.levels;
}

}  // namespace

std::vector<float> VirtualCamera::RateOfShownPattern() {
  const VirtualProjector& projector = rig_.virtual_projector();
  const Pattern& shown = projector.current();
  if (prepared_material_ != rig_.material_generation()) prepared_.clear();
  // A newly announced window that holds the shown pattern: all of it in one pass.
  if (projector.upcoming_generation() != prepared_upcoming_) {
    const std::vector<Pattern>& upcoming = projector.upcoming();
    const bool announced = std::any_of(upcoming.begin(), upcoming.end(),
                                       [&](const Pattern& p) { return SamePattern(p, shown); });
    if (announced) {
      prepared_upcoming_ = projector.upcoming_generation();
      prepared_material_ = rig_.material_generation();
      prepared_.clear();
      try {
        std::vector<std::vector<float>> rates = rig_.model().ElectronRates(upcoming);
        for (size_t i = 0; i < upcoming.size(); ++i) {
          prepared_.emplace_back(upcoming[i], std::move(rates[i]));
        }
        rates_rendered_ahead_ += upcoming.size();
      } catch (const InputError&) {
        // One of them does not fit the projector: the shown one is rendered alone below, and
        // reports its own error if it is the one.
      }
    }
  }
  for (auto it = prepared_.begin(); it != prepared_.end(); ++it) {
    if (SamePattern(it->first, shown)) {
      std::vector<float> rate = std::move(it->second);
      prepared_.erase(it);
      ++rates_from_windows_;
      return rate;
    }
  }
  return rig_.model().ElectronRate(shown);
}

CameraInfo VirtualCamera::Info() const {
  const Rig& rig = rig_.rig();
  CameraInfo info;
  info.id = "virtual";
  info.model = "simulated camera (" + rig.name + ")";
  info.width = rig.camera.width;
  info.height = rig.camera.height;
  info.layout = rig.sensor.layout;
  info.bit_depth = rig.sensor.bit_depth;
  info.min_exposure_us = 10;
  info.max_exposure_us = 10e6;
  info.gain_unit = "e-/DN";
  return info;
}

double VirtualCamera::SetExposure(double exposure_us) {
  const CameraInfo info = Info();
  if (!(exposure_us >= info.min_exposure_us && exposure_us <= info.max_exposure_us)) {
    throw DeviceError("virtual camera: ExposureTime " + std::to_string(exposure_us) +
                      " us is outside [" + std::to_string(info.min_exposure_us) + ", " +
                      std::to_string(info.max_exposure_us) + "] us");
  }
  // Like real cameras, quantize to the sensor's line time (here 1 us).
  exposure_us_ = std::round(exposure_us);
  return exposure_us_;
}

Frame VirtualCamera::Grab(std::chrono::milliseconds /*timeout*/) {
  const Rig& rig = rig_.rig();
  Clock& clock = rig_.clock();
  const int64_t period_us = static_cast<int64_t>(std::llround(1e6 / rig.timing.frame_rate_hz));
  const int64_t start = std::max(clock.NowUs(), last_start_us_ + period_us);
  clock.SleepUs(start - clock.NowUs());
  last_start_us_ = start;
  const VirtualProjector& projector = rig_.virtual_projector();
  if (cached_generation_ != projector.generation() ||
      cached_material_ != rig_.material_generation()) {
    if (projector.generation() == 0) {
      // Nothing shown yet: the projector is dark (its black level still lights the sample).
      Pattern dark;
      dark.width = rig.projector.lens.width;
      dark.height = rig.projector.lens.height;
      dark.bit_depth = rig.projector.bit_depth;
      dark.levels.assign(static_cast<size_t>(dark.width) * dark.height, 0);
      cached_rate_ = rig_.model().ElectronRate(dark);
    } else {
      cached_rate_ = RateOfShownPattern();
    }
    cached_generation_ = projector.generation();
    cached_material_ = rig_.material_generation();
  }
  Frame frame = rig_.model().RenderFromRate(cached_rate_, exposure_us_, next_index_,
                                            rig_.options().noise);
  frame.frame_id = frame_id_++;
  frame.timestamp_us = start;
  ++next_index_;
  clock.SleepUs(static_cast<int64_t>(std::llround(exposure_us_ + 1e3 * rig.timing.readout_ms)));
  return frame;
}

VirtualRig::VirtualRig(const Rig& rig, std::shared_ptr<const Brdf> material,
                       const Options& options)
    : options_(options),
      optics_(std::make_unique<OpticalSystem>(rig)),
      maps_(std::make_unique<RigMaps>(LoadOrBuildRigMaps(
          *optics_, options.cache_dir.empty() ? DefaultCacheDir() : options.cache_dir,
          options.progress))),
      projector_(*this),
      camera_(*this) {
  SetMaterial(std::move(material));
}

void VirtualRig::SetMaterial(std::shared_ptr<const Brdf> material) {
  ZBRDF_ASSERT(material != nullptr, "virtual rig needs a material");
  model_.reset();
  material_ = std::move(material);
  ForwardModelOptions model_options;
  model_options.seed = options_.seed;
  model_options.progress = options_.progress;
  if (options_.transport_cache) {
    model_options.cache_dir =
        (options_.cache_dir.empty() ? DefaultCacheDir() : options_.cache_dir) + "/transport";
  }
  model_ = std::make_unique<ForwardModel>(*optics_, *maps_, *material_, model_options);
  ++material_generation_;
}

}  // namespace zbrdf
