#include "drivers/rig_sync.h"

#include <cmath>

#include "basis/error.h"

namespace zbrdf {

std::string SyncModeName(SyncMode mode) {
  return mode == SyncMode::kHardware ? "hardware" : "software";
}

SyncMode ParseSyncMode(const std::string& name) {
  if (name == "hardware") return SyncMode::kHardware;
  if (name == "software") return SyncMode::kSoftware;
  throw InputError("unknown sync mode '" + name + "'; use hardware or software");
}

PatternCapture::PatternCapture(Camera& camera, Projector& projector, Clock& clock,
                               const RigSyncConfig& config)
    : camera_(camera), projector_(projector), clock_(clock), config_(config) {
  if (!(config.software_settle_ms >= 0) || !(config.hardware_settle_ms >= 0)) {
    throw InputError("sync settle times must be >= 0 ms");
  }
  camera_.SetTriggerMode(config.mode == SyncMode::kHardware ? TriggerMode::kHardwareLine
                                                            : TriggerMode::kSoftware);
}

Frame PatternCapture::ShowAndGrab(const Pattern& pattern, std::chrono::milliseconds timeout) {
  projector_.Show(pattern);
  last_show_us_ = clock_.NowUs();
  const double settle_ms =
      config_.mode == SyncMode::kHardware ? config_.hardware_settle_ms : config_.software_settle_ms;
  clock_.SleepUs(static_cast<int64_t>(std::llround(settle_ms * 1000.0)));
  return camera_.Grab(timeout);
}

}  // namespace zbrdf
