// Capture jobs on the virtual rig, shared by `zbrdf simulate` and `zbrdf capture --material`.
#pragma once

#include <functional>
#include <future>
#include <memory>
#include <string>

#include "acquisition/capture_job.h"
#include "acquisition/ground_truth.h"
#include "brdf/brdf.h"
#include "rig/rig.h"

namespace zbrdf {

// How the virtual camera's frames reach the capture session.
enum class CameraLink {
  kDirect,  // the session grabs from the virtual camera
  // Through the real GigE Vision stack: the virtual camera's frames are served by an Aravis fake
  // camera on 127.0.0.1 (drivers/fake_gige_camera.h) and grabbed by the AravisCamera driver, in
  // the sensor's pixel format (BayerRG12 for the thesis rig), with software triggers. Frames are
  // keyed on the plan's frame index as on the direct link, so both sessions hold the same frames.
  // Needs 127.0.0.1:3956 free (one fake at a time).
  kGigEFake,
};

struct GigEFakeOptions {
  double lost_packet_ratio = 0;  // probability that the fake drops each GVSP packet
  // > 0: the fake stops answering (as a camera losing power) once this many frames reached the
  // session in this run; the capture then fails with the driver's DeviceError (tests of resume).
  int stop_after_frames = 0;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

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
  CameraLink camera_link = CameraLink::kDirect;
  GigEFakeOptions gige;
  CaptureJobOptions job;
  // Called with the plan (after job.on_plan) and the material the rig images, before the first
  // planned frame: for work that needs both and can overlap the capture (zbrdf simulate's true
  // coefficients).
  std::function<void(const CapturePlan&, const std::shared_ptr<const Brdf>&)> on_plan_material;
};

struct VirtualCaptureOutcome {
  CaptureJobResult result;
  std::shared_ptr<const Brdf> material;
  double device_time_s = 0;  // on the virtual rig's clock: what the real rig would take
  double setup_seconds = 0;  // maps and transport
  size_t transport_entries = 0;
  // CameraLink::kGigEFake: frames the driver dropped for missing packets and captured again.
  uint64_t incomplete_frames = 0;
};

// Builds the virtual rig (as built) for the material and runs the capture job on it with the
// calibration. A resumed session keeps its own material, seed, noise setting, faults and
// calibration (from session.json) unless they are given explicitly and agree.
VirtualCaptureOutcome RunVirtualCapture(VirtualCaptureArgs args);

// The material's true coefficients for a virtual capture (zbrdf simulate, the simulator's
// benchmark), integrated on a thread of their own from the plan on: the plan gives the layout
// processing lays the coefficients out in (zone, order, exitant grid; ZonalLayout), so they are
// ready by the last frame instead of after it. Declare it before RunVirtualCapture: if the
// capture throws, its destructor waits for the integration.
class EarlyTruth {
 public:
  EarlyTruth(const GroundTruthOptions& options, std::string cache_dir)
      : options_(options), cache_dir_(std::move(cache_dir)) {}
  // Sets args->on_plan_material to start the integration when the capture has its plan, laid
  // out by args->job.processing as it is now (set it first).
  void StartAtPlan(VirtualCaptureArgs* args);
  // The true coefficients for the capture's: the early ones where their layout is zonal's, else
  // (no plan was reached, or processing laid them out otherwise) integrated now. Once.
  GroundTruth Get(const Brdf& material, const ZonalData& zonal);

 private:
  GroundTruthOptions options_;
  std::string cache_dir_;
  ZonalData layout_;
  std::future<GroundTruth> early_;
};

// The rig description a session was captured with (session.json), parsed and validated.
Rig SessionRig(const std::string& session_dir);
// The calibration folder a session was captured with ("" : the nominal calibration).
std::string SessionCalibrationFolder(const std::string& session_dir);
// A text file's contents; InputError naming `what` and the path if it cannot be read.
std::string ReadTextFile(const std::string& path, const std::string& what);

}  // namespace zbrdf
