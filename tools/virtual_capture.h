// Capture jobs on the virtual rig, shared by `zbrdf simulate` and `zbrdf capture --material`.
#pragma once

#include <memory>
#include <string>

#include "acquisition/capture_job.h"
#include "fitting/brdf.h"
#include "simulate/rig.h"

namespace zbrdf {

struct VirtualCaptureArgs {
  Rig rig;                  // preset applied
  std::string preset_name;  // for session.json
  std::string material_spec;
  uint64_t seed = 1;
  bool noise = true;
  CaptureJobOptions job;
};

struct VirtualCaptureOutcome {
  CaptureJobResult result;
  std::shared_ptr<const Brdf> material;
  double device_time_s = 0;   // on the virtual rig's clock: what the real rig would take
  double setup_seconds = 0;   // maps and transport
  size_t transport_entries = 0;
};

// Builds the virtual rig for the material and runs the capture job on it. A resumed session
// keeps its own material, seed and noise setting (from session.json) unless they are given
// explicitly and agree.
VirtualCaptureOutcome RunVirtualCapture(VirtualCaptureArgs args);

// The rig description a session was captured with (session.json), parsed and validated.
Rig SessionRig(const std::string& session_dir);

}  // namespace zbrdf
