// Projector-camera synchronization: show a pattern, then capture a frame exposed under it.
//
// Two ways, chosen by the rig file's sync.mode (docs/hardware-rig.md, "Sync"):
//
//  hardware  The projector's trigger output (DLPC350 TRIG_OUT_1/2, one pulse per displayed
//            frame) is wired to the camera's input line; the camera runs in
//            TriggerMode::kHardwareLine. After Show() the capture waits `hardware_settle_ms`
//            (at least one display frame, so that the next trigger belongs to a frame that
//            shows the new pattern) and then Grab() takes the next line-triggered frame; frames
//            exposed before the call are dropped by the driver. Exposure starts are locked to
//            the display's frames, which removes the jitter of software timing and lets
//            exposures avoid the DMD's frame changes.
//  software  The fallback when there is no trigger cable (or the projector has no trigger
//            output): the camera runs in TriggerMode::kSoftware, and the capture waits
//            `software_settle_ms` after Show() before triggering. The settle time must cover the
//            whole chain from XPutImage to light on the sample (X server, HDMI, the projector's
//            frame buffer, typically 2-4 display frames); `zbrdf check-rig` measures it.
#pragma once

#include <chrono>
#include <string>

#include "drivers/camera.h"
#include "drivers/clock.h"
#include "drivers/projector.h"

namespace zbrdf {

enum class SyncMode { kHardware, kSoftware };

// "hardware" / "software"; ParseSyncMode throws InputError naming the accepted values.
std::string SyncModeName(SyncMode mode);
SyncMode ParseSyncMode(const std::string& name);

struct RigSyncConfig {
  SyncMode mode = SyncMode::kSoftware;
  double software_settle_ms = 100;  // Show() to software trigger
  double hardware_settle_ms = 40;   // Show() to the first usable line trigger
};

class PatternCapture {
 public:
  // Sets the camera's trigger mode for `config.mode`. All references must outlive this object.
  PatternCapture(Camera& camera, Projector& projector, Clock& clock, const RigSyncConfig& config);

  // Shows the pattern, waits the settle time on `clock`, and grabs one frame (see the file
  // comment). The frame's timestamp_us is on `clock` when the camera uses the same clock.
  Frame ShowAndGrab(const Pattern& pattern, std::chrono::milliseconds timeout);

  // When the last ShowAndGrab's Show() returned, on `clock`.
  int64_t last_show_us() const { return last_show_us_; }

 private:
  Camera& camera_;
  Projector& projector_;
  Clock& clock_;
  RigSyncConfig config_;
  int64_t last_show_us_ = 0;
};

}  // namespace zbrdf
