// Files written whole or not at all: a crash, Ctrl-C, SIGKILL or a full disk leaves the previous
// file (or none), never a truncated one (docs/session-folder.md, "Crashes, full disks and
// concurrent runs"). Everything zbrdf writes goes through here: session and calibration folders,
// exports, reports, pictures and caches. Libraries that write through their own streams (OpenEXR,
// libtiff, OpenCV) encode into memory and hand the bytes to WriteFileAtomically.
// tests/write_sites_test.cc fails on a file write anywhere else in the sources.
//
// Temporary files are "<final name>.tmp<PID>" in the final file's folder; a killed process
// leaves them behind, and RemoveStaleTemporaryFiles() removes those of processes that are gone.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "basis/error.h"

namespace zbrdf {

// A write that failed. what() names the final file (never the temporary one), says why, and for
// a full disk how much the file needed and how much was free, then what to do:
//   disk full writing sessions/x/zonal.exr (needs about 2.1 MB, 0.3 MB free): free space and
//   run the command again
// Commands replace the last part with their own next step (WithNextStep), e.g. "continue with
// the same command plus --resume".
class FileWriteError : public InputError {
 public:
  // error_number: the errno of the failed call (ENOSPC, EDQUOT, EFBIG, EACCES, EROFS, EIO, ...).
  FileWriteError(std::string path, int error_number, uint64_t bytes_needed, uint64_t bytes_free,
                 std::string next_step = "run the command again");

  const std::string& path() const { return path_; }
  int error_number() const { return error_number_; }
  uint64_t bytes_needed() const { return bytes_needed_; }
  uint64_t bytes_free() const { return bytes_free_; }
  // ENOSPC, EDQUOT or EFBIG: more space (or a larger file size limit) would let it succeed.
  bool out_of_space() const;
  // The same error with another next step.
  FileWriteError WithNextStep(const std::string& next_step) const;

 private:
  std::string path_;
  int error_number_;
  uint64_t bytes_needed_, bytes_free_;
  std::string next_step_;
};

// Writes bytes to path via a temporary file in the same folder: write (whole, retrying short
// writes), fsync, rename over path, fsync of the folder. On any failure the temporary file is
// removed, the previous file at path is untouched, and FileWriteError is thrown.
void WriteFileAtomically(const std::string& path, const std::string& bytes);

// Appends bytes to path (created if missing) and fsyncs it: for journals, whose lines are added
// one at a time. On failure the file is cut back to its previous length (so a full disk leaves no
// partial line; a kill can, and the journal's reader repairs it) and FileWriteError is thrown.
void AppendToFile(const std::string& path, const std::string& bytes);

// Cuts the file at path to `length` bytes and fsyncs it (a journal's torn last line).
// FileWriteError on failure.
void TruncateFile(const std::string& path, uint64_t length);

// Writes a cache entry: the parts, in order, to a temporary file in path's folder, renamed over
// path. No fsync (an entry lost to a power cut is rebuilt, and its reader checks it whole) and
// not a fault-injection site: a cache is never what a crash test protects. Safe for concurrent
// writers, also on a shared file system (a cluster's shards): one writer per entry (the first to
// create "<path>.writing"; the others return false and go on without writing), a temporary name
// unique per host, process and call, and an atomic rename, so a reader sees the old entry or the
// new one, whole. Returns false, leaving no temporary file and the previous entry (if any), when
// another writer holds the entry, the folder cannot be created or the disk is full: callers go on
// without the cache.
bool WriteCacheFile(const std::string& path, const std::vector<std::string_view>& parts);

// The bytes of n objects at data, or of a vector's elements, as they lie in memory: a part of a
// cache entry (WriteCacheFile) written without copying.
template <typename T>
std::string_view ObjectBytes(const T* data, size_t n = 1) {
  static_assert(std::is_trivially_copyable_v<T>, "only objects whose bytes are their value");
  return {reinterpret_cast<const char*>(data), n * sizeof(T)};
}
template <typename T>
std::string_view ObjectBytes(const std::vector<T>& v) {
  return ObjectBytes(v.data(), v.size());
}

// The temporary name WriteFileAtomically uses for path in this process.
std::string TemporaryFileName(const std::string& path);
// True for a name of the form TemporaryFileName gives ("<name>.tmp<PID>").
bool IsTemporaryFileName(const std::string& name);
// Removes the temporary files ("<name>.tmp<PID>") in `folder` (not its subfolders) whose process
// is no longer running; returns the names removed. A process's own temporaries and those of
// running processes are kept.
std::vector<std::string> RemoveStaleTemporaryFiles(const std::string& folder);

// Free bytes for an unprivileged user on the file system holding `path` (or its nearest
// existing parent); 0 if unknown.
uint64_t FreeBytes(const std::string& path);
// "512 bytes", "2.1 kB", "2.1 MB", "1.3 GB" (decimal units).
std::string FormatBytes(uint64_t bytes);

// Fault injection, for the crash-test harness (tests/tools/crash_test.cc) and the helper binary
// it runs (tests/tools/zbrdf_faults.cc): each WriteFileAtomically or AppendToFile call is one
// write operation, counted from 1 in the process; the planned fault hits the operation-th one
// (counting only paths that contain path_contains, if it is set).
enum class WriteFault {
  kNone,
  kNoSpace,      // `fraction` of the bytes written, then write() fails with ENOSPC
  kIoError,      // all bytes written, then fsync() fails with EIO
  kShortWrites,  // every write() call moves only a few bytes: not an error, the file comes out
                 // whole
  kKill,  // `fraction` of the bytes written (1: all, fsync'ed, not yet renamed), then SIGKILL
};
struct WriteFaultPlan {
  WriteFault fault = WriteFault::kNone;
  int64_t operation = 0;
  double fraction = 0.5;  // in [0, 1]
  std::string path_contains;
};
// Replaces the plan (and restarts the count of matching operations). Process-wide.
void SetWriteFaultPlan(const WriteFaultPlan& plan);
// Write operations started in this process so far (all paths).
int64_t WriteOperationCount();
// "nospace", "eio", "short", "kill" <-> WriteFault; ParseWriteFault throws InputError.
std::string WriteFaultName(WriteFault fault);
WriteFault ParseWriteFault(const std::string& name);

}  // namespace zbrdf
