#include "acquisition/session.h"

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "acquisition/frame_file.h"
#include "acquisition/json_integer.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/hash.h"
#include "basis/option_checker.h"

namespace zbrdf {

namespace {

std::string ReadBytes(const std::string& path, bool* ok) {
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

std::string Checksum(const std::string& bytes) {
  const uint64_t h = Fnv1a64(bytes);
  char out[32];
  std::snprintf(out, sizeof(out), "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return out;
}

std::string UtcNow() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace

std::string FileChecksum(const std::string& path) {
  bool ok = true;
  const std::string bytes = ReadBytes(path, &ok);
  return ok ? Checksum(bytes) : std::string();
}

nlohmann::json JournalEntry::ToJson() const {
  return {{"index", index},       {"lobe", lobe},           {"exposure", exposure},
          {"repeat", repeat},     {"exposure_us_requested", exposure_us_requested},
          {"exposure_us", exposure_us}, {"frame_id", frame_id}, {"timestamp_us", timestamp_us},
          {"wall_time", wall_time}, {"file", file},         {"checksum", checksum},
          {"width", width},       {"height", height},       {"bit_depth", bit_depth},
          {"layout", layout}};
}

JournalEntry JournalEntry::FromJson(const nlohmann::json& j) {
  JournalEntry e;
  e.index = JsonIntegerAt<int>(j, "index", "journal entry");
  e.lobe = j.at("lobe").get<std::string>();
  e.exposure = JsonIntegerAt<int>(j, "exposure", "journal entry");
  e.repeat = JsonIntegerAt<int>(j, "repeat", "journal entry");
  e.exposure_us_requested = j.at("exposure_us_requested").get<double>();
  e.exposure_us = j.at("exposure_us").get<double>();
  e.frame_id = JsonIntegerAt<uint64_t>(j, "frame_id", "journal entry");
  e.timestamp_us = JsonIntegerAt<int64_t>(j, "timestamp_us", "journal entry");
  e.wall_time = j.at("wall_time").get<std::string>();
  e.file = j.at("file").get<std::string>();
  e.checksum = j.at("checksum").get<std::string>();
  e.width = JsonIntegerAt<int>(j, "width", "journal entry");
  e.height = JsonIntegerAt<int>(j, "height", "journal entry");
  e.bit_depth = JsonIntegerAt<int>(j, "bit_depth", "journal entry");
  e.layout = j.at("layout").get<std::string>();
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

std::string SessionPath(const std::string& dir, const std::string& name) {
  return dir + "/" + name;
}

bool SessionFolder::Exists(const std::string& path) {
  return std::filesystem::exists(std::filesystem::path(path) / kSessionFile);
}

SessionFolder SessionFolder::Create(const std::string& path, const nlohmann::json& session) {
  if (Exists(path)) {
    throw InputError("folder " + path +
                     " already holds a session; resume it (--resume) or choose another --out");
  }
  std::error_code ec;
  for (const char* sub : {"", kFramesFolder, kHdrFolder}) {
    std::filesystem::create_directories(std::filesystem::path(path) / sub, ec);
    if (ec) throw InputError("cannot create session folder " + path + ": " + ec.message());
  }
  SessionFolder folder(path);
  folder.UpdateSession(session);
  return folder;
}

SessionFolder SessionFolder::Open(const std::string& path) {
  SessionFolder folder(path);
  bool ok = true;
  const std::string text = ReadBytes(SessionPath(path, kSessionFile), &ok);
  if (!ok) {
    throw InputError("no session in " + path + " (session.json missing); run zbrdf capture or "
                     "zbrdf simulate with --out " + path + " first");
  }
  folder.session_ = nlohmann::json::parse(text, nullptr, false);
  if (folder.session_.is_discarded() || !folder.session_.is_object()) {
    throw InputError(SessionPath(path, kSessionFile) +
                     " is not valid JSON; the session folder is damaged");
  }
  return folder;
}

SessionFolder SessionFolder::OpenForWriting(const std::string& path) {
  SessionFolder folder = Open(path);
  std::error_code ec;
  for (const char* sub : {kFramesFolder, kHdrFolder}) {
    std::filesystem::create_directories(std::filesystem::path(path) / sub, ec);
    if (ec) throw InputError("cannot create " + path + "/" + sub + ": " + ec.message());
  }
  return folder;
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
  e.checksum = Checksum(bytes);
  e.width = frame.width;
  e.height = frame.height;
  e.bit_depth = frame.bit_depth;
  e.layout = PixelLayoutName(frame.layout);
  e.exposure_us = frame.exposure_us;
  e.frame_id = frame.frame_id;
  e.timestamp_us = frame.timestamp_us;
  e.wall_time = UtcNow();
  return e;
}

void SessionFolder::AppendJournal(const JournalEntry& entry) {
  const std::string line = entry.ToJson().dump() + "\n";
  const std::string path = SessionPath(path_, kJournalFile);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  if (fd < 0) throw InputError("cannot append to " + path);
  const bool ok = ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size()) &&
                  ::fsync(fd) == 0;
  ::close(fd);
  if (!ok) throw InputError("appending to " + path + " failed (disk full?)");
}

std::vector<JournalEntry> SessionFolder::ReadJournal() const {
  std::map<int, JournalEntry> latest;
  std::ifstream in(SessionPath(path_, kJournalFile));
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded()) continue;  // a line cut short by a crash
    try {
      JournalEntry e = JournalEntry::FromJson(j);
      latest[e.index] = std::move(e);
    } catch (const std::exception&) {
      // A damaged line: that frame will be captured again.
    }
  }
  std::vector<JournalEntry> out;
  for (auto& [index, e] : latest) out.push_back(std::move(e));
  return out;
}

bool SessionFolder::FrameIsIntact(const JournalEntry& entry) const {
  return FileChecksum(SessionPath(path_, entry.file)) == entry.checksum;
}

Frame SessionFolder::ReadFrame(const JournalEntry& entry) const {
  const std::string path = SessionPath(path_, entry.file);
  bool ok = true;
  const std::string bytes = ReadBytes(path, &ok);
  if (!ok) throw InputError("frame " + path + " is missing; resume the capture to take it again");
  if (Checksum(bytes) != entry.checksum) {
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
  f.data = DecodeFrameFile(bytes, entry.width, entry.height, "frame " + path);
  return f;
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
  for (JournalEntry& e : session.ReadJournal()) {
    if (e.index >= plan.frame_count()) continue;
    if (session.FrameIsIntact(e)) {
      done[e.index] = std::move(e);
    } else {
      ++journaled_but_broken;
    }
  }
  const int total = plan.frame_count();
  long progress_done = static_cast<long>(done.size());
  Report(options.progress, {"capture", progress_done, total, "frames"});
  const int64_t start_us = clock.NowUs();
  const int per_lobe = static_cast<int>(plan.exposures_us.size()) * plan.repeats;
  for (int lobe = 0; lobe < static_cast<int>(plan.lobes.size()); ++lobe) {
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
      projector.Show(patterns.Load(lobe));
      clock.SleepUs(static_cast<int64_t>(options.settle_us));
      for (int index : missing) {
        if (options.interrupt && options.interrupt->load()) {
          result.interrupted = true;
          result.device_time_s = (clock.NowUs() - start_us) * 1e-6;
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
        JournalEntry entry = session.WriteFrame(index, frame);
        entry.lobe = plan.lobes[lobe].Name();
        entry.exposure = pf.exposure;
        entry.repeat = pf.repeat;
        entry.exposure_us_requested = requested;
        session.AppendJournal(entry);
        done[index] = entry;
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
  result.frames_recaptured = std::min(journaled_but_broken, result.frames_captured);
  result.device_time_s = (clock.NowUs() - start_us) * 1e-6;
  return result;
}

}  // namespace zbrdf
