#include "acquisition/session.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "acquisition/frame_file.h"
#include "acquisition/frame_writer.h"
#include "acquisition/json_integer.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/hash.h"
#include "basis/option_checker.h"

namespace zbrdf {

namespace {

namespace fs = std::filesystem;

constexpr char kLineCheckKey[] = ",\"line_check\":\"";

std::string ReadBytes(const std::string& path, bool* ok) {
  std::error_code error;
  if (fs::is_directory(path, error)) {
    *ok = false;
    return {};
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *ok = false;
    return {};
  }
  std::ostringstream s;
  s << in.rdbuf();
  *ok = static_cast<bool>(in) || in.eof();
  return s.str();
}

std::string Checksum(std::string_view bytes) {
  const uint64_t h = Fnv1a64(bytes);
  char out[32];
  std::snprintf(out, sizeof(out), "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return out;
}

std::string UtcNow(const char* format = "%Y-%m-%dT%H:%M:%SZ") {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof(buf), format, &tm);
  return buf;
}

// The command line of this process, for the lock file ("zbrdf process sessions/x").
std::string CommandLineOfThisProcess() {
  bool ok = true;
  std::string text = ReadBytes("/proc/self/cmdline", &ok);
  if (!ok || text.empty()) return "pid " + std::to_string(::getpid());
  for (char& c : text) {
    if (c == '\0') c = ' ';
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  const size_t slash = text.substr(0, text.find(' ')).rfind('/');
  if (slash != std::string::npos) text = text.substr(slash + 1);
  return text.size() > 200 ? text.substr(0, 200) + "..." : text;
}

// The locks this process holds, by canonical folder (SessionLock is re-entrant per process).
struct HeldLock {
  int fd = -1;
  int handles = 0;
};
std::mutex g_locks_mutex;
std::map<std::string, HeldLock> g_locks;

// What a folder that is to receive a new session holds, other than what a run killed before its
// session.json leaves: one entry per item, e.g. "journal.jsonl", "frames/ (150 files)".
std::vector<std::string> UnexpectedContents(const std::string& path) {
  std::vector<std::string> found;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(path, error)) {
    const std::string name = entry.path().filename().string();
    if (name == kLockFile) continue;
    if (entry.is_directory(error) && (name == kFramesFolder || name == kHdrFolder)) {
      int files = 0;
      int temporary = 0;
      for (const auto& inner : fs::directory_iterator(entry.path(), error)) {
        ++files;
        temporary += IsTemporaryFileName(inner.path().filename().string());
      }
      if (files > temporary) found.push_back(name + "/ (" + std::to_string(files) + " files)");
      continue;
    }
    if (IsTemporaryFileName(name) && entry.is_regular_file(error)) continue;
    found.push_back(entry.is_directory(error) ? name + "/" : name);
  }
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace

std::string FrameFileChecksum(std::string_view bytes) {
  char out[32];
  std::snprintf(out, sizeof(out), "xxh3-64:%016llx",
                static_cast<unsigned long long>(Xxh3_64(bytes)));
  return out;
}

bool FrameFileChecksumMatches(const std::string& recorded, std::string_view bytes) {
  if (recorded.rfind("xxh3-64:", 0) == 0) return recorded == FrameFileChecksum(bytes);
  // Journals written before XXH3.
  if (recorded.rfind("fnv1a64:", 0) == 0) return recorded == Checksum(bytes);
  return false;
}

std::string FileChecksum(const std::string& path) {
  bool ok = true;
  const std::string bytes = ReadBytes(path, &ok);
  return ok ? FrameFileChecksum(bytes) : std::string();
}

nlohmann::json JournalEntry::ToJson() const {
  nlohmann::json j = {{"index", index},
                      {"lobe", lobe},
                      {"exposure", exposure},
                      {"repeat", repeat},
                      {"exposure_us_requested", exposure_us_requested},
                      {"exposure_us", exposure_us},
                      {"frame_id", frame_id},
                      {"timestamp_us", timestamp_us},
                      {"wall_time", wall_time},
                      {"file", file},
                      {"checksum", checksum},
                      {"width", width},
                      {"height", height},
                      {"bit_depth", bit_depth},
                      {"layout", layout}};
  if (!session_id.empty()) j["session_id"] = session_id;
  return j;
}

std::string JournalEntry::ToLine() const {
  const std::string body = ToJson().dump();
  return body.substr(0, body.size() - 1) + kLineCheckKey + Checksum(body) + "\"}\n";
}

JournalEntry JournalEntry::FromJson(const nlohmann::json& j) {
  const std::string where = "journal entry";
  const auto text = [&](const char* key) {
    if (!j.contains(key) || !j.at(key).is_string()) {
      throw InputError(where + " field '" + key + "' is missing or not a string");
    }
    return j.at(key).get<std::string>();
  };
  const auto number = [&](const char* key) {
    if (!j.contains(key) || !j.at(key).is_number()) {
      throw InputError(where + " field '" + key + "' is missing or not a number");
    }
    return j.at(key).get<double>();
  };
  JournalEntry e;
  e.index = JsonIntegerAt<int>(j, "index", where);
  e.lobe = text("lobe");
  e.exposure = JsonIntegerAt<int>(j, "exposure", where);
  e.repeat = JsonIntegerAt<int>(j, "repeat", where);
  e.exposure_us_requested = number("exposure_us_requested");
  e.exposure_us = number("exposure_us");
  e.frame_id = JsonIntegerAt<uint64_t>(j, "frame_id", where);
  e.timestamp_us = JsonIntegerAt<int64_t>(j, "timestamp_us", where);
  e.wall_time = text("wall_time");
  e.file = text("file");
  e.checksum = text("checksum");
  e.width = JsonIntegerAt<int>(j, "width", where);
  e.height = JsonIntegerAt<int>(j, "height", where);
  e.bit_depth = JsonIntegerAt<int>(j, "bit_depth", where);
  e.layout = text("layout");
  if (j.contains("session_id")) e.session_id = text("session_id");
  if (e.index < 0 || e.width <= 0 || e.height <= 0 || e.bit_depth < 1 || e.bit_depth > 16 ||
      !(e.exposure_us > 0) || e.file.find("..") != std::string::npos) {
    throw InputError("journal entry " + std::to_string(e.index) + " has out-of-range fields");
  }
  return e;
}

std::string FrameFileName(int index) {
  char name[40];
  std::snprintf(name, sizeof(name), "%s/f%06d.tiff", kFramesFolder, index);
  return name;
}

std::string FitReportFileName(const std::string& model) {
  return kFitReportPrefix + model + ".json";
}

std::string ShFileName(const std::string& target) { return kShFilePrefix + target + ".exr"; }

std::string TornJournalFileName(int n) {
  return std::string(kJournalFile) + ".torn-" + std::to_string(n);
}

std::string SessionPath(const std::string& dir, const std::string& name) {
  return dir + "/" + name;
}

std::shared_ptr<SessionLock> SessionLock::Acquire(const std::string& dir) {
  std::error_code error;
  const std::string key = fs::canonical(dir, error).string();
  if (error) throw InputError("cannot lock session " + dir + ": " + error.message());
  std::lock_guard<std::mutex> guard(g_locks_mutex);
  auto held = g_locks.find(key);
  if (held == g_locks.end()) {
    const std::string path = SessionPath(dir, kLockFile);
    // O_CLOEXEC: a child process (a fake camera) must not inherit, and so keep, the lock.
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) {
      throw FileWriteError(path, errno, 0, FreeBytes(path),
                           "run the command again (a session's writer needs its lock file)");
    }
    // Busy: name the holder. Retried for a moment while nobody can be named: a process probing
    // the lock (CheckCaptureJob) holds it for an instant, and a writer that has just left or
    // just arrived (not yet written its PID) is not the one to name.
    std::string holder;
    int flock_error = 0;
    for (int attempt = 0; attempt < 10; ++attempt) {
      if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {
        flock_error = 0;
        break;
      }
      flock_error = errno;
      if (flock_error != EWOULDBLOCK) break;
      holder = Holder(dir);
      if (!holder.empty()) break;
      ::usleep(5000);
    }
    if (flock_error != 0) {
      ::close(fd);
      if (flock_error != EWOULDBLOCK) {
        throw InputError("cannot lock session " + dir + " (" + std::strerror(flock_error) +
                         "); its file system may not support flock(2)");
      }
      long pid = 0;
      std::sscanf(holder.c_str(), "pid %ld", &pid);
      if (holder.empty()) holder = "another process";
      throw SessionBusyError("session " + dir + " is being written by " + holder +
                                 "; one process writes a session at a time: wait for it to "
                                 "finish (or stop it), then run this command again",
                             pid);
    }
    // Who holds it, for the next writer's message. The lock file is rewritten in place: it must
    // stay the inode the lock is on (not a project output; tests/write_sites_test.cc).
    const std::string text = "pid " + std::to_string(::getpid()) + ": " +
                             CommandLineOfThisProcess() + ", since " + UtcNow() + "\n";
    if (::ftruncate(fd, 0) != 0 ||
        ::pwrite(fd, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size())) {
      // The lock holds regardless; only the next writer's message lacks the PID.
    }
    held = g_locks.emplace(key, HeldLock{fd, 0}).first;
  }
  ++held->second.handles;
  return std::shared_ptr<SessionLock>(new SessionLock(key));
}

SessionLock::~SessionLock() {
  std::lock_guard<std::mutex> guard(g_locks_mutex);
  auto held = g_locks.find(key_);
  if (held == g_locks.end()) return;
  if (--held->second.handles == 0) {
    ::close(held->second.fd);  // releases the flock
    g_locks.erase(held);
  }
}

std::string SessionLock::Holder(const std::string& dir) {
  const std::string path = SessionPath(dir, kLockFile);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return "";
  // A shared lock we can take means no writer holds it.
  if (::flock(fd, LOCK_SH | LOCK_NB) == 0) {
    ::close(fd);
    return "";
  }
  char text[512];
  std::string holder;
  // The holder writes its line right after locking: until then the file holds the previous
  // writer's, whose process is gone. Give it a moment.
  for (int attempt = 0; attempt < 20; ++attempt) {
    const ssize_t n = ::pread(fd, text, sizeof(text) - 1, 0);
    holder = n > 0 ? std::string(text, static_cast<size_t>(n)) : std::string();
    while (!holder.empty() && (holder.back() == '\n' || holder.back() == '\0')) holder.pop_back();
    long pid = 0;
    if (std::sscanf(holder.c_str(), "pid %ld", &pid) == 1 && pid > 0 &&
        (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM)) {
      break;  // a running process: the holder
    }
    holder.clear();
    ::usleep(5000);
  }
  ::close(fd);
  return holder;
}

std::string SessionRepairs::Summary() const {
  std::string out;
  if (torn_journal_bytes > 0) {
    out = "cut a torn last line from the journal (" + FormatBytes(torn_journal_bytes) +
          ", kept in " + torn_journal_copy + "; its frame is taken again)";
  }
  if (!temporary_files_removed.empty()) {
    if (!out.empty()) out += "; ";
    out += "removed " + std::to_string(temporary_files_removed.size()) +
           " temporary file(s) of a killed run";
  }
  return out;
}

bool SessionFolder::Exists(const std::string& path) {
  return fs::exists(fs::path(path) / kSessionFile);
}

void CheckNewSessionFolder(const std::string& path) {
  if (SessionFolder::Exists(path)) {
    throw InputError("folder " + path +
                     " already holds a session; resume it (--resume), choose another --out, or "
                     "give --force-new to move it aside and start a new one");
  }
  std::error_code error;
  if (!fs::exists(path, error)) return;
  if (!fs::is_directory(path, error)) {
    throw InputError("--out " + path + " is a file, not a folder; choose another --out");
  }
  const std::vector<std::string> found = UnexpectedContents(path);
  if (found.empty()) return;
  std::string list;
  for (size_t k = 0; k < found.size() && k < 6; ++k) list += (k ? ", " : "") + found[k];
  if (found.size() > 6) list += " and " + std::to_string(found.size() - 6) + " more";
  throw InputError("folder " + path + " is not empty but holds no session.json (found " + list +
                   "): frames there could come from any plan, exposure or material, so none is "
                   "trusted. Choose another --out, or give --force-new to move the folder aside "
                   "(to " +
                   path + ".before-<time>; nothing is deleted) and start a new session");
}

std::string MoveSessionFolderAside(const std::string& path) {
  std::error_code error;
  if (!fs::exists(path, error)) return "";
  if (fs::is_directory(path, error) && UnexpectedContents(path).empty() &&
      !SessionFolder::Exists(path)) {
    return "";
  }
  std::shared_ptr<SessionLock> lock;
  if (fs::is_directory(path, error) && fs::exists(SessionPath(path, kLockFile), error)) {
    lock = SessionLock::Acquire(path);  // nobody may be writing what is moved
  }
  std::string base = path;
  while (base.size() > 1 && base.back() == '/') base.pop_back();
  std::string target = base + ".before-" + UtcNow("%Y%m%dT%H%M%SZ");
  for (int n = 2; fs::exists(target, error); ++n) {
    target = base + ".before-" + UtcNow("%Y%m%dT%H%M%SZ") + "-" + std::to_string(n);
  }
  fs::rename(path, target, error);
  if (error) {
    throw InputError("cannot move " + path + " aside to " + target + ": " + error.message() +
                     "; move or rename it yourself, or choose another --out");
  }
  return target;
}

SessionFolder SessionFolder::Create(const std::string& path, const nlohmann::json& session) {
  CheckNewSessionFolder(path);
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec) throw InputError("cannot create session folder " + path + ": " + ec.message());
  SessionFolder folder(path);
  folder.lock_ = SessionLock::Acquire(path);
  CheckNewSessionFolder(path);  // again, under the lock: another process may have been first
  for (const char* sub : {kFramesFolder, kHdrFolder}) {
    fs::create_directories(fs::path(path) / sub, ec);
    if (ec) throw InputError("cannot create session folder " + path + ": " + ec.message());
  }
  folder.RepairForWriting();  // temporary files of a run killed before its session.json
  nlohmann::json info = session;
  info.erase("session_id");
  info["session_id"] = Checksum(info.dump()).substr(std::string("fnv1a64:").size());
  folder.UpdateSession(info);
  return folder;
}

SessionFolder SessionFolder::Open(const std::string& path) {
  SessionFolder folder(path);
  bool ok = true;
  const std::string text = ReadBytes(SessionPath(path, kSessionFile), &ok);
  if (!ok) {
    std::error_code error;
    const bool has_journal = fs::exists(SessionPath(path, kJournalFile), error);
    throw InputError("no session in " + path + " (session.json missing" +
                     (has_journal ? "; a journal and frames without it cannot be trusted" : "") +
                     "); run zbrdf capture or zbrdf simulate with --out " + path +
                     (has_journal ? " --force-new" : "") + " first");
  }
  folder.session_ = nlohmann::json::parse(text, nullptr, false);
  if (folder.session_.is_discarded() || !folder.session_.is_object()) {
    throw InputError(SessionPath(path, kSessionFile) +
                     " is not valid JSON; the session folder is damaged");
  }
  return folder;
}

SessionFolder SessionFolder::OpenForWriting(const std::string& path) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) {
    throw InputError("no session in " + path +
                     " (no such folder); run zbrdf capture or zbrdf "
                     "simulate with --out " +
                     path + " first");
  }
  std::shared_ptr<SessionLock> lock = SessionLock::Acquire(path);
  SessionFolder folder = Open(path);  // under the lock: the latest session.json
  folder.lock_ = std::move(lock);
  for (const char* sub : {kFramesFolder, kHdrFolder}) {
    fs::create_directories(fs::path(path) / sub, ec);
    if (ec) throw InputError("cannot create " + path + "/" + sub + ": " + ec.message());
  }
  folder.RepairForWriting();
  return folder;
}

void SessionFolder::RepairForWriting() {
  for (const std::string& sub :
       {std::string(), std::string(kFramesFolder) + "/", std::string(kHdrFolder) + "/"}) {
    for (const std::string& name :
         RemoveStaleTemporaryFiles(sub.empty() ? path_ : SessionPath(path_, sub))) {
      repairs_.temporary_files_removed.push_back(sub + name);
    }
  }
  const std::string journal = SessionPath(path_, kJournalFile);
  bool ok = true;
  const std::string bytes = ReadBytes(journal, &ok);
  if (!ok || bytes.empty() || bytes.back() == '\n') return;
  // A line torn by a crash or a full disk: appending would glue the next line onto it. Keep it
  // (journal.jsonl.torn-<n>), then cut it away; its frame is captured again.
  const size_t keep = bytes.rfind('\n') == std::string::npos ? 0 : bytes.rfind('\n') + 1;
  int n = 1;
  std::error_code error;
  while (fs::exists(SessionPath(path_, TornJournalFileName(n)), error)) ++n;
  repairs_.torn_journal_copy = TornJournalFileName(n);
  repairs_.torn_journal_bytes = bytes.size() - keep;
  WriteFileAtomically(SessionPath(path_, repairs_.torn_journal_copy), bytes.substr(keep));
  TruncateFile(journal, keep);
}

std::string SessionFolder::session_id() const {
  const auto it = session_.find("session_id");
  return it != session_.end() && it->is_string() ? it->get<std::string>() : std::string();
}

std::string SessionFolder::material() const {
  const auto it = session_.find("material");
  return it != session_.end() && it->is_string() ? it->get<std::string>() : std::string();
}

void SessionFolder::UpdateSession(const nlohmann::json& session) {
  session_ = session;
  WriteFileAtomically(SessionPath(path_, kSessionFile), session.dump(2) + "\n");
}

JournalEntry SessionFolder::WriteFrame(int index, const Frame& frame) {
  const std::string bytes = EncodeFrameFile(frame);
  const std::string name = FrameFileName(index);
  WriteFileAtomically(SessionPath(path_, name), bytes);
  JournalEntry e;
  e.index = index;
  e.file = name;
  e.checksum = FrameFileChecksum(bytes);
  e.width = frame.width;
  e.height = frame.height;
  e.bit_depth = frame.bit_depth;
  e.layout = PixelLayoutName(frame.layout);
  e.exposure_us = frame.exposure_us;
  e.frame_id = frame.frame_id;
  e.timestamp_us = frame.timestamp_us;
  e.wall_time = UtcNow();
  e.session_id = session_id();
  return e;
}

void SessionFolder::AppendJournal(const JournalEntry& entry) {
  AppendToFile(SessionPath(path_, kJournalFile), entry.ToLine());
}

std::vector<JournalEntry> SessionFolder::ReadJournal() const { return ReadJournalLines().entries; }

JournalReading SessionFolder::ReadJournalLines() const {
  JournalReading reading;
  bool ok = true;
  const std::string bytes = ReadBytes(SessionPath(path_, kJournalFile), &ok);
  std::map<int, JournalEntry> latest;
  size_t begin = 0;
  int number = 0;
  while (ok && begin < bytes.size()) {
    const size_t end = bytes.find('\n', begin);
    if (end == std::string::npos) {
      reading.torn_tail = true;  // a line cut short by a crash: not trusted
      break;
    }
    const std::string line = bytes.substr(begin, end - begin);
    begin = end + 1;
    ++number;
    if (line.empty()) continue;
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    bool intact = !j.is_discarded() && j.is_object();
    if (intact && j.contains("line_check")) {
      // The check covers the line's bytes up to the key (closed with '}').
      const size_t at = line.rfind(kLineCheckKey);
      intact = at != std::string::npos && j["line_check"].is_string() &&
               j["line_check"].get<std::string>() == Checksum(line.substr(0, at) + "}");
    }
    if (!intact) {
      reading.damaged_lines.push_back(number);
      continue;
    }
    try {
      JournalEntry e = JournalEntry::FromJson(j);
      latest[e.index] = std::move(e);
    } catch (const std::exception&) {
      reading.damaged_lines.push_back(number);  // that frame will be captured again
    }
  }
  for (auto& [index, e] : latest) reading.entries.push_back(std::move(e));
  return reading;
}

bool SessionFolder::FrameIsIntact(const JournalEntry& entry) const {
  bool ok = true;
  const std::string bytes = ReadBytes(SessionPath(path_, entry.file), &ok);
  return ok && FrameFileChecksumMatches(entry.checksum, bytes);
}

Frame SessionFolder::ReadFrame(const JournalEntry& entry) const {
  const std::string path = SessionPath(path_, entry.file);
  bool ok = true;
  const std::string bytes = ReadBytes(path, &ok);
  if (!ok) throw InputError("frame " + path + " is missing; resume the capture to take it again");
  if (!FrameFileChecksumMatches(entry.checksum, bytes)) {
    throw InputError("frame " + path + " does not match its journal checksum (truncated or "
                     "corrupt); resume the capture to take it again");
  }
  Frame f;
  f.width = entry.width;
  f.height = entry.height;
  f.bit_depth = entry.bit_depth;
  f.layout = ParsePixelLayout(entry.layout);
  f.exposure_us = entry.exposure_us;
  f.frame_id = entry.frame_id;
  f.timestamp_us = entry.timestamp_us;
  try {
    f.data = DecodeFrameFile(bytes, entry.width, entry.height, "frame " + path);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + "; resume the capture (--resume) to take it again");
  }
  return f;
}

std::string JournalEntryMismatch(const JournalEntry& e, const CapturePlan& plan,
                                 const std::string& session_id, bool exposures_planned) {
  const std::string line = "frame " + std::to_string(e.index) + "'s journal line";
  if (!session_id.empty() && !e.session_id.empty() && e.session_id != session_id) {
    return line + " belongs to session " + e.session_id + ", not " + session_id;
  }
  if (e.index < 0 || e.index >= plan.frame_count()) {
    return line + ": the plan has " + std::to_string(plan.frame_count()) + " frames";
  }
  const PlannedFrame pf = plan.Frame(e.index);
  const std::string lobe = plan.lobes[pf.lobe].Name();
  if (e.lobe != lobe || e.exposure != pf.exposure || e.repeat != pf.repeat) {
    return line + " says lobe " + e.lobe + ", exposure " + std::to_string(e.exposure) +
           ", repeat " + std::to_string(e.repeat) + "; the plan says lobe " + lobe + ", exposure " +
           std::to_string(pf.exposure) + ", repeat " + std::to_string(pf.repeat);
  }
  if (e.file != FrameFileName(e.index)) {
    return line + " names file " + e.file + ", not " + FrameFileName(e.index);
  }
  const double planned = plan.exposures_us[pf.exposure];
  if ((exposures_planned || pf.exposure == 0) &&
      std::abs(e.exposure_us_requested - planned) > 1e-9 * planned) {
    char text[160];
    std::snprintf(text, sizeof(text), " requested %.6g us; the plan says %.6g us",
                  e.exposure_us_requested, planned);
    return line + text;
  }
  return "";
}

void CaptureOptions::Validate() const {
  OptionChecker check("CaptureOptions");
  check.Above("grab_timeout (ms)", static_cast<double>(grab_timeout.count()), 0)
      .Require(settle_us >= 0 && std::isfinite(settle_us), "settle_us",
               "must be >= 0 and finite (got " + FormatOptionValue(settle_us) + ")")
      .ThrowIfInvalid();
}

CaptureResult RunCapture(SessionFolder& session, const CapturePlan& plan,
                         const PatternSet& patterns, Camera& camera, Projector& projector,
                         Clock& clock, const CaptureOptions& options) {
  options.Validate();
  CaptureResult result;
  std::map<int, JournalEntry> done;
  int journaled_but_broken = 0;
  const JournalReading journal = session.ReadJournalLines();
  result.journal_lines_rejected = static_cast<int>(journal.damaged_lines.size());
  if (!journal.damaged_lines.empty()) {
    result.first_rejection = "journal line " + std::to_string(journal.damaged_lines[0]) +
                             " is damaged (it fails its check or is not a journal entry)";
  }
  const CameraInfo camera_info = camera.Info();
  const std::string session_id = session.session_id();
  for (const JournalEntry& e : journal.entries) {
    if (e.index >= plan.frame_count()) continue;  // bands an adaptive session did not keep
    // A line is trusted only if it is one of this session's planned frames, from this camera.
    std::string mismatch =
        JournalEntryMismatch(e, plan, session_id, /*exposures_planned=*/!options.exposure_us);
    if (mismatch.empty() &&
        (e.width != camera_info.width || e.height != camera_info.height ||
         e.layout != PixelLayoutName(camera_info.layout) || e.bit_depth != camera_info.bit_depth)) {
      mismatch = "frame " + std::to_string(e.index) + "'s journal line describes a " +
                 std::to_string(e.width) + "x" + std::to_string(e.height) + " " + e.layout +
                 " frame; the camera delivers " + std::to_string(camera_info.width) + "x" +
                 std::to_string(camera_info.height) + " " + PixelLayoutName(camera_info.layout);
    }
    if (!mismatch.empty()) {
      if (result.first_rejection.empty()) result.first_rejection = mismatch;
      ++result.journal_lines_rejected;
      continue;
    }
    if (session.FrameIsIntact(e)) {
      done[e.index] = e;
    } else {
      ++journaled_but_broken;
    }
  }
  const int total = plan.frame_count();
  long progress_done = static_cast<long>(done.size());
  Report(options.progress, {"capture", progress_done, total, "frames"});
  const int64_t start_us = clock.NowUs();
  const int per_lobe = static_cast<int>(plan.exposures_us.size()) * plan.repeats;
  const int lobe_count = static_cast<int>(plan.lobes.size());
  // A projector that renders several patterns at once (Projector::PatternsAhead, the virtual
  // one) is told the next lobes with frames to take, from the one about to be shown, but for
  // those skip_lobe_ahead leaves out; their patterns are loaded once, for both. A pattern file
  // that fails to load ends the window, so its error comes at its own lobe, as without one.
  const int ahead = std::max(0, projector.PatternsAhead());
  std::map<int, Pattern> window;
  auto pattern_of = [&](int lobe) -> Pattern {
    if (ahead < 2) return patterns.Load(lobe);
    if (!window.count(lobe)) {
      window.clear();
      std::vector<Pattern> upcoming;
      for (int l = lobe; l < lobe_count && static_cast<int>(upcoming.size()) < ahead; ++l) {
        bool missing = false;
        for (int k = 0; k < per_lobe && !missing; ++k) missing = !done.count(l * per_lobe + k);
        if (!missing || (l != lobe && options.skip_lobe_ahead && options.skip_lobe_ahead(l))) {
          continue;
        }
        try {
          upcoming.push_back(patterns.Load(l));
        } catch (const InputError&) {
          if (l == lobe) throw;
          break;
        }
        window[l] = upcoming.back();
      }
      projector.Upcoming(upcoming);
    }
    Pattern pattern = std::move(window.at(lobe));
    window.erase(lobe);
    return pattern;
  };
  // Frames are written and journaled on the writer's thread while the next ones are grabbed
  // (acquisition/frame_writer.h); `done` gets their entries once the writer has drained.
  FrameWriter writer(session);
  for (int lobe = 0; lobe < lobe_count; ++lobe) {
    if (options.skip_lobe && options.skip_lobe(lobe)) {
      progress_done += per_lobe;
      Report(options.progress, {"capture", progress_done, total, "frames"});
      if (options.on_lobe_complete) options.on_lobe_complete(lobe, {});
      if (options.stop_after_lobe && options.stop_after_lobe(lobe)) {
        result.stopped_after_lobe = lobe;
        break;
      }
      continue;
    }
    std::vector<Frame> frames(per_lobe);
    std::vector<int> missing;
    for (int k = 0; k < per_lobe; ++k) {
      const int index = lobe * per_lobe + k;
      if (done.count(index)) continue;
      missing.push_back(index);
    }
    if (!missing.empty()) {
      projector.Show(pattern_of(lobe));
      clock.SleepUs(static_cast<int64_t>(options.settle_us));
      for (int index : missing) {
        if (options.interrupt && options.interrupt->load()) {
          result.interrupted = true;
          result.device_time_s = (clock.NowUs() - start_us) * 1e-6;
          writer.Drain();  // every frame taken is on disk and journaled
          return result;
        }
        const PlannedFrame pf = plan.Frame(index);
        double requested = plan.exposures_us[pf.exposure];
        if (options.exposure_us && pf.exposure > 0) {
          std::vector<const Frame*> shorter;
          for (int e = 0; e < pf.exposure; ++e) {
            const int k = plan.FrameIndex(lobe, e, pf.repeat) - lobe * per_lobe;
            if (frames[k].data.empty()) {
              frames[k] = session.ReadFrame(done.at(lobe * per_lobe + k));
              ++result.frames_reused;
            }
            shorter.push_back(&frames[k]);
          }
          requested = options.exposure_us(lobe, pf.exposure, shorter);
        }
        camera.SetExposure(requested);
        camera.SetNextFrameIndex(static_cast<uint64_t>(index));
        Frame frame = camera.Grab(options.grab_timeout);
        JournalEntry plan_fields;
        plan_fields.lobe = plan.lobes[lobe].Name();
        plan_fields.exposure = pf.exposure;
        plan_fields.repeat = pf.repeat;
        plan_fields.exposure_us_requested = requested;
        writer.Add(index, frame, plan_fields);  // a copy: the lobe's processing keeps this one
        frames[index - lobe * per_lobe] = std::move(frame);
        ++result.frames_captured;
        Report(options.progress, {"capture", ++progress_done, total, "frames"});
      }
    }
    // Earlier runs' frames of this lobe.
    for (int k = 0; k < per_lobe; ++k) {
      const int index = lobe * per_lobe + k;
      if (frames[k].data.empty()) {
        frames[k] = session.ReadFrame(done.at(index));
        ++result.frames_reused;
      }
    }
    if (options.on_lobe_complete) options.on_lobe_complete(lobe, frames);
    if (options.stop_after_lobe && options.stop_after_lobe(lobe)) {
      result.stopped_after_lobe = lobe;
      break;
    }
  }
  result.device_time_s = (clock.NowUs() - start_us) * 1e-6;
  for (JournalEntry& e : writer.Drain()) done[e.index] = std::move(e);
  result.frames_recaptured = std::min(journaled_but_broken, result.frames_captured);
  // What is on disk must say what this run believes: every frame taken or kept has its line.
  std::map<int, std::string> on_disk;
  for (const JournalEntry& e : session.ReadJournal()) on_disk[e.index] = e.checksum;
  for (const auto& [index, e] : done) {
    const auto it = on_disk.find(index);
    if (it == on_disk.end() || it->second != e.checksum) {
      throw InputError("journal " + SessionPath(session.path(), kJournalFile) + " lost frame " +
                       std::to_string(index) + "'s line while the capture ran; resume the " +
                       "capture (--resume) to take that frame again");
    }
  }
  return result;
}

}  // namespace zbrdf
