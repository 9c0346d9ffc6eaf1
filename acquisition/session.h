// A capture session on disk, and the runner that fills it.
//
// Folder layout (docs/session-folder.md):
//   session.json    rig (canonical YAML and hash), plan, calibration reference, material (for
//                   simulated sessions), seed, devices, software version, session id
//   frames/         raw frames, lossless 16-bit TIFF/zstd (frame_file.h), f<index>.tiff
//                   (index: the plan's frame index); each records the checksum of its samples
//   journal.jsonl   one JSON line per frame written: index, lobe, exposure (requested, actual),
//                   repeat, frame id, timestamps, file, XXH3 checksum of the file, session id,
//                   and the line's own check
//   hdr/            HDR image per lobe (RGB half-float OpenEXR, for viewing)
//   zonal.exr       the zonal coefficients (acquisition/zonal.h)
//   report.json     what was done, how long it took, and how accurate it is
//   session.lock    the writer lock (SessionLock); holds the writer's PID and command line
//
// A session is what its session.json and journal say it is. Every file is written atomically
// (basis/atomic_file.h); frames before their journal line is appended and synced, so a crash or
// Ctrl-C loses at most the frame in flight. A journal line is trusted only if it passes its own
// check and matches the session's id and plan; a frame only if its file matches the line's
// checksum (and, when decoded, its own). Anything else is captured again on --resume. An
// existing session is never overwritten, and a non-empty folder without session.json is never
// taken for one. One process writes a session at a time (SessionLock); readers never wait.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "acquisition/patterns.h"
#include "acquisition/plan.h"
#include "basis/error.h"
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
inline constexpr char kPriorFitFile[] = "fit-prior.exr";   // zbrdf fit --model prior
// zbrdf fit --model auto: the recommended model and why (docs/prior.md)
inline constexpr char kAutoFitFile[] = "fit-auto.json";
inline constexpr char kShFile[] = "sh.exr";                // an SH file under its plain name
inline constexpr char kLockFile[] = "session.lock";        // SessionLock
inline constexpr char kFitReportPrefix[] = "fit-";
inline constexpr char kShFilePrefix[] = "sh-";
// frames/f<index, 6 digits>.tiff
std::string FrameFileName(int index);
// fit-<model>.json: a fit's report (for analytic models also the model: its "spec").
std::string FitReportFileName(const std::string& model);
// sh-<target>.exr: zbrdf convert's SH file for a target basis (basis/target_basis.h).
std::string ShFileName(const std::string& target);
// journal.jsonl.torn-<n>: the n-th torn last line cut from the journal, kept as it was.
std::string TornJournalFileName(int n);
// <dir>/<name>.
std::string SessionPath(const std::string& dir, const std::string& name);

// A second writer of a session that another process is writing.
class SessionBusyError : public InputError {
 public:
  SessionBusyError(const std::string& message, long holder_pid)
      : InputError(message), holder_pid_(holder_pid) {}
  long holder_pid() const { return holder_pid_; }  // 0 if the holder could not be identified

 private:
  long holder_pid_;
};

// The writer lock of a session folder: an advisory flock(2) on <session>/session.lock, held by
// capture, resume and process for as long as they write (docs/session-folder.md, "One writer at
// a time"). A second writer fails at once with SessionBusyError naming the holder's PID and
// command line; readers take no lock and never wait. The kernel releases the lock when its holder
// exits, even by SIGKILL, so a stale session.lock file never blocks anyone. The lock is per
// process and re-entrant: a process that holds it gets another handle to the same lock.
class SessionLock {
 public:
  // `dir` must exist. Throws SessionBusyError if another process holds the lock, InputError if
  // the lock file cannot be created.
  static std::shared_ptr<SessionLock> Acquire(const std::string& dir);
  // Who holds dir's lock now ("pid 1234: zbrdf process sessions/x, since 2026-11-26T10:24:35Z"),
  // or "" if nobody does (or the holder cannot be named). Never waits for the lock; waits at most
  // 0.1 s for a writer that has just taken it to write its PID.
  static std::string Holder(const std::string& dir);
  ~SessionLock();
  SessionLock(const SessionLock&) = delete;
  SessionLock& operator=(const SessionLock&) = delete;

 private:
  explicit SessionLock(std::string key) : key_(std::move(key)) {}
  std::string key_;  // the canonical folder path in the process's table of held locks
};

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
  std::string checksum;      // "xxh3-64:<16 hex digits>" of the file's bytes ("fnv1a64:" before)
  int width = 0, height = 0, bit_depth = 0;
  std::string layout;
  std::string session_id;  // session.json "session_id" ("" in journals of earlier versions)

  nlohmann::json ToJson() const;
  static JournalEntry FromJson(const nlohmann::json& j);
  // The journal line: ToJson() with "line_check": "fnv1a64:<hex>" of the rest of the line
  // appended as the last key, and a newline.
  std::string ToLine() const;
};

// The journal as read: the last intact line per frame index, and what was not trusted.
struct JournalReading {
  std::vector<JournalEntry> entries;  // ascending index
  // 1-based numbers of complete lines that failed their check, were not JSON or lacked fields.
  std::vector<int> damaged_lines;
  bool torn_tail = false;  // the journal ends in a line without its newline (ignored)
};

// What opening a session for writing repaired (SessionFolder::OpenForWriting).
struct SessionRepairs {
  uint64_t torn_journal_bytes = 0;  // cut from the journal's end (a line torn by a crash)
  std::string torn_journal_copy;    // where they were kept (journal.jsonl.torn-<n>)
  std::vector<std::string> temporary_files_removed;  // left by killed runs, relative names

  bool any() const { return torn_journal_bytes > 0 || !temporary_files_removed.empty(); }
  // One line for people: "cut a torn last journal line (57 bytes, kept in ...); removed 2
  // temporary files of killed runs"; "" if nothing was repaired.
  std::string Summary() const;
};

class SessionFolder {
 public:
  // Creates `path` (and frames/, hdr/), takes its writer lock and writes session.json, adding
  // "session_id" (FNV-1a 64 of the rest of session.json). Throws InputError if the folder already
  // holds a session (resume it, or choose another folder) or holds anything else
  // (CheckNewSessionFolder), SessionBusyError if another process writes it.
  static SessionFolder Create(const std::string& path, const nlohmann::json& session);
  // Opens an existing session to read it: reads session.json and writes nothing. Throws
  // InputError if there is none or session.json is damaged.
  static SessionFolder Open(const std::string& path);
  // Opens an existing session to add to it (resume a capture, re-process its frames): takes its
  // writer lock (SessionBusyError if another process holds it), reads session.json, creates
  // frames/ and hdr/ if they are missing, cuts a torn last journal line away (keeping it in
  // journal.jsonl.torn-<n>) and removes temporary files of killed runs; repairs() says what.
  static SessionFolder OpenForWriting(const std::string& path);
  // True if `path` holds a session (a session.json), whether or not it can be read.
  static bool Exists(const std::string& path);

  const std::string& path() const { return path_; }
  const nlohmann::json& session() const { return session_; }
  // session.json "session_id" ("" for sessions of earlier versions).
  std::string session_id() const;
  // A simulated session's true material (its material spec, session.json "material"); "" for a
  // measured session.
  std::string material() const;
  // The writer lock (null for a folder opened with Open()): keep it to go on writing in the
  // folder after this object is gone (report.json).
  std::shared_ptr<SessionLock> lock() const { return lock_; }
  const SessionRepairs& repairs() const { return repairs_; }
  // Rewrites session.json (atomically).
  void UpdateSession(const nlohmann::json& session);

  // Writes the frame file atomically; returns the journal entry to append (without timing).
  JournalEntry WriteFrame(int index, const Frame& frame);
  // Appends the entry's line (JournalEntry::ToLine) and syncs it; FileWriteError on failure, with
  // nothing of the line left in the journal.
  void AppendJournal(const JournalEntry& entry);
  // The journal's trusted entries, the last one per index (ReadJournalLines().entries).
  std::vector<JournalEntry> ReadJournal() const;
  JournalReading ReadJournalLines() const;
  // Reads a journaled frame, verifying the file's checksum against the entry and the samples
  // against the checksum the file records; throws InputError naming the file if it is missing,
  // truncated or corrupt.
  Frame ReadFrame(const JournalEntry& entry) const;
  // True if the entry's file exists and matches its checksum.
  bool FrameIsIntact(const JournalEntry& entry) const;

 private:
  explicit SessionFolder(std::string path) : path_(std::move(path)) {}
  void RepairForWriting();
  std::string path_;
  nlohmann::json session_;
  std::shared_ptr<SessionLock> lock_;
  SessionRepairs repairs_;
};

// Whether a new session may be created in `path`: it does not exist, or holds nothing but what a
// run killed before writing session.json leaves (an empty frames/ and hdr/, session.lock,
// temporary files). Throws InputError otherwise: for a session, pointing at --resume; for other
// contents, naming what is there and pointing at --force-new. Writes nothing.
void CheckNewSessionFolder(const std::string& path);
// Moves a non-empty `path` aside to "<path>.before-<UTC time>" (never deletes anything) so that a
// new session can be created there; returns the new name, or "" if there was nothing to move.
// Throws SessionBusyError if a process is writing the session there.
std::string MoveSessionFolderAside(const std::string& path);

// Why a journal entry cannot be frame entry.index of this session ("" if it can): its session id
// (when both have one), index, lobe, exposure index, repeat and file must be the plan's, and so
// must its requested exposure when `exposures_planned` (false where a capture decides exposures
// while it runs, CaptureOptions::exposure_us: then only the first exposure of a bracket is).
std::string JournalEntryMismatch(const JournalEntry& entry, const CapturePlan& plan,
                                 const std::string& session_id, bool exposures_planned);

// The checksum a journal line records for a frame file's bytes: XXH3 64-bit,
// "xxh3-64:<16 hex digits>" (basis/hash.h).
std::string FrameFileChecksum(std::string_view bytes);
// Whether bytes match a recorded checksum: "xxh3-64:<hex>", or "fnv1a64:<hex>" (FNV-1a 64, what
// journals written before XXH3 record).
bool FrameFileChecksumMatches(const std::string& recorded, std::string_view bytes);
// FrameFileChecksum of a file's bytes; "" if unreadable.
std::string FileChecksum(const std::string& path);

struct CaptureOptions {
  std::chrono::milliseconds grab_timeout{5000};
  double settle_us = 0;                    // after each new pattern
  ProgressCallback progress;
  const std::atomic<bool>* interrupt = nullptr;  // set by a signal handler: stop after a frame
  // Called when every frame of a lobe is taken (in plan order), with its frames, so that
  // processing runs while the capture goes on; the last of them may still be being written
  // (acquisition/frame_writer.h: RunCapture returns only once every frame is on disk). Frames of
  // lobes completed in an earlier run of the session are read back from disk and passed too.
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
  // If set, what skip_lobe would say of a later lobe as things stand, without deciding it (no
  // side effects): such lobes are left out of the patterns a projector is told ahead
  // (Projector::Upcoming). A lobe it misses costs that projector a render, not a frame.
  std::function<bool(int lobe)> skip_lobe_ahead;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct CaptureResult {
  int frames_captured = 0;    // in this run
  int frames_reused = 0;      // intact frames from an earlier run
  int frames_recaptured = 0;  // journaled but missing or corrupt, captured again
  // Journal lines not trusted: damaged (failed their check) or not of this session and plan
  // (JournalEntryMismatch); their frames were captured again.
  int journal_lines_rejected = 0;
  std::string first_rejection;  // why the first was rejected, for the report
  bool interrupted = false;
  double device_time_s = 0;   // on the session clock (modeled time on the virtual rig)
  int stopped_after_lobe = -1;  // CaptureOptions::stop_after_lobe ended the capture there
};

// Runs (or resumes) the plan: for each lobe, shows its pattern, waits the settle time, and for
// each repeat and exposure grabs a frame, writes it and journals it (on a thread of its own, in
// order, while the next frame is grabbed: acquisition/frame_writer.h; an interruption or a
// device error returns or throws only once the frames taken are written). Frames already journaled,
// of this session and plan (JournalEntryMismatch), of the camera's size and layout, and intact
// are kept. At the end the journal on disk is read back: every frame of the plan must be in it.
// Throws DeviceError if a device fails (the journal keeps what was done), FileWriteError if a
// file cannot be written.
CaptureResult RunCapture(SessionFolder& session, const CapturePlan& plan,
                         const PatternSet& patterns, Camera& camera, Projector& projector,
                         Clock& clock, const CaptureOptions& options);

}  // namespace zbrdf
