// The rig self-test behind `zbrdf check-rig`: a bounded (30 s by default) run that checks, item
// by item, that frames arrive, patterns display, the projector controller is healthy, dark and
// white frames have sensible levels, and the settle time covers the measured projector-to-camera
// latency. Every item passes or fails with a reason that says what to do.
//
// Items, in order (an item that depends on a failed one fails as "skipped: ..."):
//   camera                     opened, check exposure set (camera.check_exposure_us)
//   camera.frames              `frames` grabs in the rig's sync mode all arrive; rate
//   projector.control          DLPC350 status bits and firmware version (only with USB control)
//   projector.display          black, white and checkerboard shown; read back from the screen
//                              equals what was sent (X11 displays)
//   projector.readback_latency time from sending an image to the X server showing it (X11)
//   levels.dark                black pattern: mean below dark_max_fraction of full scale
//                              (levels are measured in steady state: at least steady_state_ms
//                              after Show(), whatever the rig's settle time)
//   levels.white               white pattern: brighter than dark by white_min_contrast of full
//                              scale, and at most saturated_max_fraction of samples saturated
//   sync.latency               from Show() returning to light on the sample, bounded between two
//                              frames (first dark, first bright); must not exceed the settle time
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "drivers/camera.h"
#include "drivers/clock.h"
#include "drivers/dlpc350.h"
#include "drivers/projector.h"
#include "drivers/rig_sync.h"
#include "drivers/x11_display.h"

namespace zbrdf {

struct RigCheckItem {
  std::string name;
  bool passed = false;
  std::string detail;  // the measurement, or why it failed and what to do
};

struct RigCheckReport {
  std::vector<RigCheckItem> items;
  double seconds = 0;
  bool AllPassed() const;
};

struct RigCheckOptions {
  int frames = 10;
  double exposure_us = 10000;
  std::chrono::milliseconds grab_timeout{2000};
  double budget_s = 30;
  double dark_max_fraction = 0.10;
  double white_min_contrast = 0.10;
  double saturated_max_fraction = 0.01;
  std::chrono::milliseconds latency_window{2000};  // how long to watch for the light to arrive
  double steady_state_ms = 500;                    // wait after Show() before measuring levels

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

// `display` and `control` may be null (no read-back / no USB control). The camera must use
// `clock` for its frame timestamps (AravisCamera(options, &clock)) for sync.latency to mean
// anything.
RigCheckReport RunRigCheck(Camera& camera, Projector& projector, X11Display* display,
                           Dlpc350* control, const RigSyncConfig& sync, Clock& clock,
                           const RigCheckOptions& options);

}  // namespace zbrdf
