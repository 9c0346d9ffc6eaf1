#include "basis/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <ctime>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>

namespace zbrdf {
namespace {

namespace fs = std::filesystem;

std::string FolderOf(const std::string& path) {
  const std::string parent = fs::path(path).parent_path().string();
  return parent.empty() ? "." : parent;
}

void SyncDirectory(const std::string& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

// What failed, in words, for FileWriteError::what().
std::string Problem(const std::string& path, int error_number, uint64_t needed, uint64_t free) {
  const std::string sizes =
      " (needs about " + FormatBytes(needed) + ", " + FormatBytes(free) + " free)";
  switch (error_number) {
    case ENOSPC:
      return "disk full writing " + path + sizes + ": free space";
    case EDQUOT:
      return "disk quota exceeded writing " + path + sizes + ": free space in your quota";
    case EFBIG:
      return "file size limit reached writing " + path + " (needs about " + FormatBytes(needed) +
             "): raise the limit (ulimit -f)";
    case EACCES:
    case EPERM:
      return "permission denied writing " + path + ": make " + FolderOf(path) +
             " writable for you, or write elsewhere,";
    case EROFS:
      return "cannot write " + path + ": its file system is read-only; write elsewhere";
    case ENOENT:
    case ENOTDIR:
      return "cannot write " + path + ": folder " + FolderOf(path) +
             " does not exist; create it or check the path,";
    case EIO:
      return "I/O error writing " + path + ": the disk or its connection failed; check it";
    default:
      return "cannot write " + path + ": " + std::strerror(error_number) + "; fix that";
  }
}

// The fault plan and the operation counts (SetWriteFaultPlan).
std::mutex g_fault_mutex;
WriteFaultPlan g_plan;
int64_t g_operations = 0;
int64_t g_matching_operations = 0;

// Counts one write operation on path and returns the fault it is to suffer (kNone mostly).
WriteFaultPlan FaultFor(const std::string& path) {
  std::lock_guard<std::mutex> lock(g_fault_mutex);
  ++g_operations;
  if (g_plan.fault == WriteFault::kNone) return {};
  if (!g_plan.path_contains.empty() && path.find(g_plan.path_contains) == std::string::npos) {
    return {};
  }
  if (++g_matching_operations != g_plan.operation) return {};
  return g_plan;
}

// Writes all of bytes to fd, retrying short writes. Returns 0, or the errno of the failure. The
// injected faults act here: kShortWrites limits each call, kNoSpace and kKill stop after their
// fraction of the bytes.
int WriteAll(int fd, const std::string& bytes, const WriteFaultPlan& fault) {
  size_t limit = bytes.size();
  if (fault.fault == WriteFault::kNoSpace || fault.fault == WriteFault::kKill) {
    limit = static_cast<size_t>(std::clamp(fault.fraction, 0.0, 1.0) * bytes.size());
  }
  const size_t chunk = fault.fault == WriteFault::kShortWrites
                           ? std::max<size_t>(1, bytes.size() / 7)
                           : bytes.size();
  size_t written = 0;
  while (written < limit) {
    const size_t n = std::min(chunk, limit - written);
    const ssize_t done = ::write(fd, bytes.data() + written, n);
    if (done < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    if (done == 0) return EIO;
    written += static_cast<size_t>(done);
  }
  if (fault.fault == WriteFault::kKill && written < bytes.size()) ::raise(SIGKILL);
  if (fault.fault == WriteFault::kNoSpace) return ENOSPC;
  return 0;
}

int Fsync(int fd, const WriteFaultPlan& fault) {
  if (::fsync(fd) != 0) return errno;
  return fault.fault == WriteFault::kIoError ? EIO : 0;
}

}  // namespace

FileWriteError::FileWriteError(std::string path, int error_number, uint64_t bytes_needed,
                               uint64_t bytes_free, std::string next_step)
    : InputError(Problem(path, error_number, bytes_needed, bytes_free) + " and " + next_step),
      path_(std::move(path)),
      error_number_(error_number),
      bytes_needed_(bytes_needed),
      bytes_free_(bytes_free),
      next_step_(std::move(next_step)) {}

bool FileWriteError::out_of_space() const {
  return error_number_ == ENOSPC || error_number_ == EDQUOT || error_number_ == EFBIG;
}

FileWriteError FileWriteError::WithNextStep(const std::string& next_step) const {
  return FileWriteError(path_, error_number_, bytes_needed_, bytes_free_, next_step);
}

std::string TemporaryFileName(const std::string& path) {
  return path + ".tmp" + std::to_string(::getpid());
}

bool IsTemporaryFileName(const std::string& name) {
  const size_t at = name.rfind(".tmp");
  if (at == std::string::npos || at == 0 || at + 4 >= name.size()) return false;
  const std::string digits = name.substr(at + 4);
  return digits.size() <= 9 &&
         std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
}

void TruncateFile(const std::string& path, uint64_t length) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0 || ::ftruncate(fd, static_cast<off_t>(length)) != 0 || ::fsync(fd) != 0) {
    const int error = errno;
    if (fd >= 0) ::close(fd);
    throw FileWriteError(path, error, 0, FreeBytes(path));
  }
  ::close(fd);
}

void WriteFileAtomically(const std::string& path, const std::string& bytes) {
  const WriteFaultPlan fault = FaultFor(path);
  const std::string tmp = TemporaryFileName(path);
  const auto fail = [&](int error_number, int fd) {
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());
    throw FileWriteError(path, error_number, bytes.size(), FreeBytes(path));
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(errno, -1);
  if (const int error = WriteAll(fd, bytes, fault)) fail(error, fd);
  if (const int error = Fsync(fd, fault)) fail(error, fd);
  if (::close(fd) != 0) fail(errno, -1);
  if (fault.fault == WriteFault::kKill) ::raise(SIGKILL);  // whole and synced, not renamed
  if (std::rename(tmp.c_str(), path.c_str()) != 0) fail(errno, -1);
  SyncDirectory(FolderOf(path));
}

bool WriteCacheFile(const std::string& path, const std::vector<std::string_view>& parts) {
  std::error_code error;
  fs::create_directories(FolderOf(path), error);
  // One writer per entry: the first to create "<entry>.writing" writes it; the others (other
  // threads, processes or, on a shared file system, hosts building the same entry) go on without
  // writing. A claim older than 10 minutes is a writer that died: it is taken over.
  const std::string claim = path + ".writing";
  int claim_fd = ::open(claim.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (claim_fd < 0 && errno == EEXIST) {
    struct stat st {};
    if (::stat(claim.c_str(), &st) == 0 && ::time(nullptr) - st.st_mtime > 600) {
      ::unlink(claim.c_str());
      claim_fd = ::open(claim.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    }
  }
  if (claim_fd < 0) return false;
  ::close(claim_fd);
  struct Unclaim {
    const std::string& claim;
    ~Unclaim() { ::unlink(claim.c_str()); }
  } unclaim{claim};
  // A temporary name no other writer uses, even one with the same pid on another host.
  static std::atomic<uint64_t> counter{0};
  char host[64] = {};
  ::gethostname(host, sizeof(host) - 1);
  const std::string tmp = path + ".tmp-" + host + "-" + std::to_string(::getpid()) + "-" +
                          std::to_string(counter.fetch_add(1));
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  bool ok = true;
  for (std::string_view part : parts) {
    size_t written = 0;
    while (ok && written < part.size()) {
      const ssize_t done = ::write(fd, part.data() + written, part.size() - written);
      if (done < 0 && errno == EINTR) continue;
      if (done <= 0) ok = false;
      else written += static_cast<size_t>(done);
    }
  }
  if (::close(fd) != 0) ok = false;
  if (ok && std::rename(tmp.c_str(), path.c_str()) == 0) return true;
  ::unlink(tmp.c_str());
  return false;
}

void AppendToFile(const std::string& path, const std::string& bytes) {
  const WriteFaultPlan fault = FaultFor(path);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) throw FileWriteError(path, errno, bytes.size(), FreeBytes(path));
  struct stat before {};
  const bool known = ::fstat(fd, &before) == 0;
  int error = WriteAll(fd, bytes, fault);
  if (error == 0) error = Fsync(fd, fault);
  if (error != 0) {
    // No partial line stays behind: cut the file back (shrinking needs no space).
    if (known && ::ftruncate(fd, before.st_size) == 0) ::fsync(fd);
    ::close(fd);
    throw FileWriteError(path, error, bytes.size(), FreeBytes(path));
  }
  if (::close(fd) != 0) throw FileWriteError(path, errno, bytes.size(), FreeBytes(path));
  if (fault.fault == WriteFault::kKill) ::raise(SIGKILL);  // whole and synced
}

std::vector<std::string> RemoveStaleTemporaryFiles(const std::string& folder) {
  std::vector<std::string> removed;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    if (!IsTemporaryFileName(name)) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(name.substr(name.rfind(".tmp") + 4)));
    if (pid == ::getpid() || pid <= 0) continue;
    if (::kill(pid, 0) == 0 || errno != ESRCH) continue;  // running (or not ours to judge)
    if (fs::remove(entry.path(), error)) removed.push_back(name);
  }
  std::sort(removed.begin(), removed.end());
  return removed;
}

uint64_t FreeBytes(const std::string& path) {
  fs::path p = fs::path(path).parent_path();
  std::error_code error;
  while (!p.empty() && !fs::exists(p, error)) p = p.parent_path();
  struct statvfs s {};
  if (::statvfs(p.empty() ? "." : p.c_str(), &s) != 0) return 0;
  return static_cast<uint64_t>(s.f_bavail) * s.f_frsize;
}

std::string FormatBytes(uint64_t bytes) {
  char text[32];
  if (bytes < 1000) {
    std::snprintf(text, sizeof(text), "%llu bytes", static_cast<unsigned long long>(bytes));
  } else if (bytes < 1000000) {
    std::snprintf(text, sizeof(text), "%.1f kB", bytes / 1e3);
  } else if (bytes < 1000000000) {
    std::snprintf(text, sizeof(text), "%.1f MB", bytes / 1e6);
  } else {
    std::snprintf(text, sizeof(text), "%.1f GB", bytes / 1e9);
  }
  return text;
}

void SetWriteFaultPlan(const WriteFaultPlan& plan) {
  std::lock_guard<std::mutex> lock(g_fault_mutex);
  g_plan = plan;
  g_matching_operations = 0;
}

int64_t WriteOperationCount() {
  std::lock_guard<std::mutex> lock(g_fault_mutex);
  return g_operations;
}

std::string WriteFaultName(WriteFault fault) {
  switch (fault) {
    case WriteFault::kNone:
      return "none";
    case WriteFault::kNoSpace:
      return "nospace";
    case WriteFault::kIoError:
      return "eio";
    case WriteFault::kShortWrites:
      return "short";
    case WriteFault::kKill:
      return "kill";
  }
  return "none";
}

WriteFault ParseWriteFault(const std::string& name) {
  for (WriteFault f : {WriteFault::kNone, WriteFault::kNoSpace, WriteFault::kIoError,
                       WriteFault::kShortWrites, WriteFault::kKill}) {
    if (WriteFaultName(f) == name) return f;
  }
  throw InputError("unknown write fault '" + name + "'; use none, nospace, eio, short or kill");
}

}  // namespace zbrdf
