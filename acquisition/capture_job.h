// The main job: meter, plan, capture and process a session, on any Camera and Projector.
//
// `zbrdf simulate` runs it on the virtual rig, `zbrdf capture` on a rig file's devices (or the
// virtual rig), and both resume an interrupted session from its journal. Exposure metering
// shows a full-white pattern (no lobe pattern is brighter anywhere) and picks the shortest
// exposure that keeps its brightest pixels (99.9th percentile) at 70% of the sensor's range;
// the bracket then grows by 2^stops per exposure.
#pragma once

#include <atomic>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "acquisition/adaptive.h"
#include "acquisition/plan.h"
#include "acquisition/processing.h"
#include "acquisition/rig_calibration.h"
#include "acquisition/session.h"
#include "basis/progress.h"
#include "drivers/camera.h"
#include "drivers/clock.h"
#include "drivers/projector.h"
#include "rig/rig.h"

namespace zbrdf {

struct CaptureJobOptions {
  std::string out_dir;
  bool resume = false;
  // A new session in a folder that is not empty (another session, or files without a
  // session.json): move the folder aside to "<out_dir>.before-<UTC time>" first (nothing is
  // deleted). Without it such a folder is refused (CheckNewSessionFolder).
  bool force_new = false;
  int order = 4;
  // < 0: the rig's coverage, 1.5 projector pixels (at least 0.2 deg) inside its edges.
  double zone_min_deg = -1, zone_max_deg = -1;
  int exposures = 3;
  double stops_apart = 2;
  double shortest_exposure_us = 0;  // 0: metered
  int repeats = 1;
  ProcessingOptions processing;     // hdr_folder is set to <out>/hdr
  std::string pattern_cache_dir;    // "" : <cache>/zbrdf patterns (DefaultCacheDir())
  double settle_us = -1;            // after each new pattern; < 0: the rig's timing
  ProgressCallback progress;
  // Called once the plan is known, before the first pattern is shown: the plan, and the
  // predicted capture time on the rig (PredictCaptureTimeS), for the user to see up front.
  std::function<void(const CapturePlan& plan, double predicted_s)> on_plan;
  const std::atomic<bool>* interrupt = nullptr;
  nlohmann::json session_extra;     // merged into session.json (material, seed, preset, ...)
  // enabled: `order` is the largest order allowed; bands and the second exposure of each pattern
  // are decided while capturing (acquisition/adaptive.h). A resumed session uses the options in
  // its session.json instead.
  AdaptiveOptions adaptive;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct CaptureJobResult {
  CapturePlan plan;
  CaptureResult capture;
  // The session's writer lock, still held: keep the result (or this pointer) while writing more
  // into the session (report.json); released when the last copy is gone.
  std::shared_ptr<SessionLock> lock;
  SessionRepairs repairs;   // what resuming repaired (torn journal line, temporary files)
  std::string moved_aside;  // force_new: where the folder's earlier contents went
  ProcessingStats processing;
  ZonalData zonal;                 // empty if the capture was interrupted
  double predicted_capture_time_s = 0;
  double wall_capture_s = 0;       // wall time of the capture loop (includes rendering frames)
  // Wall time from the last frame (the capture loop's end) to zonal.exr on disk: what processing
  // did not finish while the capture ran (lobes are processed as their frames arrive).
  double ready_after_last_frame_s = 0;
  double pattern_seconds = 0;
  double metered_exposure_us = 0;
  bool complete = false;
  nlohmann::json adaptive;         // adaptive sessions: AdaptiveController::Report(); else null
};

// The checks RunCaptureJob makes before it does anything, for callers to run before their own
// setup (devices, the virtual rig): the options, the output folder's state (a session to resume;
// or for a new session a folder that is empty or absent, unless force_new), and that no other
// process is writing the session (SessionBusyError). Writes nothing.
void CheckCaptureJob(const CaptureJobOptions& options);

// Throws InputError for bad options or a session that cannot be resumed, SessionBusyError if
// another process writes the session, FileWriteError (a disk full, ...) naming the file and "the
// same command plus --resume" as the next step, DeviceError when a device fails (the journal
// keeps what was captured: resume with options.resume).
CaptureJobResult RunCaptureJob(const Rig& rig, const RigCalibration& calibration, Camera& camera,
                               Projector& projector, Clock& clock, const CaptureJobOptions& options);

// Re-processes a captured session from its frames on disk (zbrdf process): HDR, zonal
// extraction, zonal.exr, holding the session's writer lock. The plan comes from session.json;
// every journal line must match it (JournalEntryMismatch) and every frame its checksums. Throws
// InputError naming a missing, corrupt or foreign frame (resume the capture to take it again),
// SessionBusyError if another process writes the session, FileWriteError naming the file (the
// previous zonal.exr and HDR images are untouched).
struct ProcessResult {
  CapturePlan plan;
  ProcessingStats processing;
  ZonalData zonal;
  double read_seconds = 0;  // reading and verifying frames
  std::shared_ptr<SessionLock> lock;  // still held, as CaptureJobResult::lock
  SessionRepairs repairs;
};
// The checks ProcessSession makes before it does anything: the session exists, its plan is
// valid, the options are, and the exitant grid resolves the plan's order; and that no other
// process writes the session. Writes nothing. Returns the plan.
CapturePlan CheckProcessSession(const std::string& session_dir, const ProcessingOptions& options);
ProcessResult ProcessSession(const std::string& session_dir, const RigCalibration& calibration,
                             const ProcessingOptions& options, const std::string& pattern_cache_dir,
                             const ProgressCallback& progress = nullptr);

// The shortest exposure of the bracket, metered on a full-white pattern (see above).
double MeterExposure(Camera& camera, Projector& projector, Clock& clock,
                     const RigCalibration& calibration, double settle_us);

}  // namespace zbrdf
