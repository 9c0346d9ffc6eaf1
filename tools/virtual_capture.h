// Capture jobs on the virtual rig, shared by `zbrdf simulate` and `zbrdf capture --material`.
#pragma once

#include <memory>
#include <string>

#include "acquisition/capture_job.h"
#include "fitting/brdf.h"
#include "simulate/rig.h"

namespace zbrdf {

struct VirtualCaptureArgs {
  Rig rig;                  // the design, preset applied
  std::string preset_name;  // for session.json
  std::string material_spec;
  // The rig as built differs from the design by this rig overlay (YAML text; "" : it does not).
  std::string faults_yaml, faults_name;
  // Calibration folder for patterns and processing ("" : the design's nominal calibration).
  std::string calibration_folder;
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

// Builds the virtual rig (as built) for the material and runs the capture job on it with the
// calibration. A resumed session keeps its own material, seed, noise setting, faults and
// calibration (from session.json) unless they are given explicitly and agree.
VirtualCaptureOutcome RunVirtualCapture(VirtualCaptureArgs args);

// The rig description a session was captured with (session.json), parsed and validated.
Rig SessionRig(const std::string& session_dir);
// The calibration folder a session was captured with ("" : the nominal calibration).
std::string SessionCalibrationFolder(const std::string& session_dir);
// A text file's contents; InputError naming `what` and the path if it cannot be read.
std::string ReadTextFile(const std::string& path, const std::string& what);

}  // namespace zbrdf
