// A capture session on disk, and the runner that fills it.
//
// Folder layout (docs/session-folder.md):
//   session.json    rig (canonical YAML and hash), plan, calibration reference, material (for
//                   simulated sessions), seed, devices, software version
//   frames/         raw frames, lossless 16-bit TIFF/zstd (frame_file.h), f<index>.tiff
//                   (index: the plan's frame index)
//   journal.jsonl   one JSON line per frame written: index, lobe, exposure (requested, actual),
//                   repeat, frame id, timestamps, file, FNV-1a checksum of the file
//   hdr/            HDR image per lobe (RGB half-float OpenEXR, for viewing)
//   zonal.exr       the zonal coefficients (acquisition/zonal.h)
//   report.json     what was done, how long it took, and how accurate it is
//
// Frames are written atomically (temporary file, fsync, rename) before their journal line is
// appended and synced, so a crash or Ctrl-C loses at most the frame in flight. A frame whose
// file is missing or fails its checksum is captured again on --resume. An existing session is
// never overwritten: Create() refuses a folder that already holds one.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "acquisition/patterns.h"
#include "acquisition/plan.h"
#include "basis/progress.h"
#include "drivers/camera.h"
#include "drivers/clock.h"
#include "drivers/projector.h"

namespace zbrdf {

// The names in a session folder, relative to it (docs/session-folder.md). Whatever reads or writes
// a session folder names its files with these.
inline constexpr char kSessionFile[] = "session.json";
inline constexpr char kJournalFile[] = "journal.jsonl";
inline constexpr char kFramesFolder[] = "frames";
inline constexpr char kHdrFolder[] = "hdr";
inline constexpr char kZonalFile[] = "zonal.exr";
inline constexpr char kReportFile[] = "report.json";       // zbrdf simulate, capture, process
inline constexpr char kReportPageFile[] = "report.html";   // zbrdf report
inline constexpr char kDBrdfFitFile[] = "fit-dbrdf.exr";   // zbrdf fit --model dbrdf
inline constexpr char kShFile[] = "sh.exr";                // an SH file under its plain name
inline constexpr char kFitReportPrefix[] = "fit-";
inline constexpr char kShFilePrefix[] = "sh-";
// frames/f<index, 6 digits>.tiff
std::string FrameFileName(int index);
// fit-<model>.json: a fit's report (for analytic models also the model: its "spec").
std::string FitReportFileName(const std::string& model);
// sh-<target>.exr: zbrdf convert's SH file for a target basis (basis/target_basis.h).
std::string ShFileName(const std::string& target);
// <dir>/<name>.
std::string SessionPath(const std::string& dir, const std::string& name);

struct JournalEntry {
  int index = 0;
  std::string lobe;
  int exposure = 0;
  int repeat = 0;
  double exposure_us_requested = 0, exposure_us = 0;
  uint64_t frame_id = 0;
  int64_t timestamp_us = 0;  // on the session's clock
  std::string wall_time;     // UTC, ISO 8601
  std::string file;          // relative to the session folder
  std::string checksum;      // "fnv1a64:<16 hex digits>" of the file's bytes
  int width = 0, height = 0, bit_depth = 0;
  std::string layout;

  nlohmann::json ToJson() const;
  static JournalEntry FromJson(const nlohmann::json& j);
};

class SessionFolder {
 public:
  // Creates `path` (and frames/, hdr/) and writes session.json. Throws InputError if the folder
  // already holds a session: use OpenForWriting() and resume it, or choose another folder.
  static SessionFolder Create(const std::string& path, const nlohmann::json& session);
  // Opens an existing session to read it: reads session.json and writes nothing. Throws
  // InputError if there is none or session.json is damaged.
  static SessionFolder Open(const std::string& path);
  // Opens an existing session to add to it (resume a capture, re-process its frames): as Open(),
  // then creates frames/ and hdr/ if they are missing.
  static SessionFolder OpenForWriting(const std::string& path);
  // True if `path` holds a session (a session.json), whether or not it can be read.
  static bool Exists(const std::string& path);

  const std::string& path() const { return path_; }
  const nlohmann::json& session() const { return session_; }
  // A simulated session's true material (its material spec, session.json "material"); "" for a
  // measured session.
  std::string material() const;
  // Rewrites session.json (atomically).
  void UpdateSession(const nlohmann::json& session);

  // Writes the frame file atomically; returns the journal entry to append (without timing).
  JournalEntry WriteFrame(int index, const Frame& frame);
  void AppendJournal(const JournalEntry& entry);
  // The journal's entries, the last one per index; a truncated last line (a crash while
  // writing it) is ignored.
  std::vector<JournalEntry> ReadJournal() const;
  // Reads a journaled frame, verifying its checksum; throws InputError naming the file if it is
  // missing, truncated or corrupt.
  Frame ReadFrame(const JournalEntry& entry) const;
  // True if the entry's file exists and matches its checksum.
  bool FrameIsIntact(const JournalEntry& entry) const;

 private:
  explicit SessionFolder(std::string path) : path_(std::move(path)) {}
  std::string path_;
  nlohmann::json session_;
};

// FNV-1a 64-bit checksum of a file's bytes, "fnv1a64:<hex>"; "" if unreadable.
std::string FileChecksum(const std::string& path);

struct CaptureOptions {
  std::chrono::milliseconds grab_timeout{5000};
  double settle_us = 0;                    // after each new pattern
  ProgressCallback progress;
  const std::atomic<bool>* interrupt = nullptr;  // set by a signal handler: stop after a frame
  // Called when every frame of a lobe is on disk (in plan order), with its frames, so that
  // processing runs while the capture goes on. Frames of lobes completed in an earlier run of
  // the session are read back from disk and passed too.
  std::function<void(int lobe, const std::vector<Frame>& frames)> on_lobe_complete;
  // Adaptive capture (acquisition/adaptive.h); both unset for a fixed plan.
  // If set, the exposure to request for frame `exposure` (> 0) of the bracket of lobe `lobe`,
  // given that lobe's frames at the shorter exposures of the same repeat (in bracket order; read
  // back from disk when an earlier run took them). Otherwise plan.exposures_us[exposure].
  std::function<double(int lobe, int exposure, const std::vector<const Frame*>& shorter)>
      exposure_us;
  // If set, called after on_lobe_complete; true ends the capture after that lobe (the rest of the
  // plan is not wanted: CaptureResult::stopped_after_lobe says where; not an interruption).
  std::function<bool(int lobe)> stop_after_lobe;
  // If set and true for a lobe, it is not captured (its pattern is not shown); on_lobe_complete
  // gets no frames for it (the processor synthesizes it: isotropy, docs/adaptive.md).
  std::function<bool(int lobe)> skip_lobe;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct CaptureResult {
  int frames_captured = 0;    // in this run
  int frames_reused = 0;      // intact frames from an earlier run
  int frames_recaptured = 0;  // journaled but missing or corrupt, captured again
  bool interrupted = false;
  double device_time_s = 0;   // on the session clock (modeled time on the virtual rig)
  int stopped_after_lobe = -1;  // CaptureOptions::stop_after_lobe ended the capture there
};

// Runs (or resumes) the plan: for each lobe, shows its pattern, waits the settle time, and for
// each repeat and exposure grabs a frame, writes it and journals it. Frames already journaled
// and intact are kept. Throws DeviceError if a device fails (the journal keeps what was done).
CaptureResult RunCapture(SessionFolder& session, const CapturePlan& plan,
                         const PatternSet& patterns, Camera& camera, Projector& projector,
                         Clock& clock, const CaptureOptions& options);

}  // namespace zbrdf
