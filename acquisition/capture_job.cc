#include "acquisition/capture_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "acquisition/session.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "rig/direction_maps.h"

namespace zbrdf {

namespace {
// Meter frames get plan indices of their own, far beyond any plan.
constexpr uint64_t kMeterFrameIndex = 1ull << 40;

// The lobes a finished adaptive session did not capture (isotropy), by name.
std::set<std::string> SkippedLobes(const nlohmann::json& session) {
  std::set<std::string> out;
  if (!session.contains("adaptive")) return out;
  const nlohmann::json& a = session["adaptive"];
  if (a.value("state", std::string()) != "done" || !a.contains("skipped_lobes")) return out;
  for (const auto& name : a["skipped_lobes"]) out.insert(name.get<std::string>());
  return out;
}
}  // namespace

double MeterExposure(Camera& camera, Projector& projector, Clock& clock,
                     const RigCalibration& c, double settle_us) {
  Pattern white;
  white.width = c.projector_width;
  white.height = c.projector_height;
  white.bit_depth = c.projector_bit_depth;
  white.levels.assign(static_cast<size_t>(white.width) * white.height,
                      static_cast<uint16_t>((1 << c.projector_bit_depth) - 1));
  projector.Show(white);
  clock.SleepUs(static_cast<int64_t>(settle_us));
  const CameraInfo info = camera.Info();
  const double range = c.saturation_dn - c.black_dn;
  double exposure = std::clamp(1000.0, info.min_exposure_us, info.max_exposure_us);
  for (int attempt = 0; attempt < 12; ++attempt) {
    exposure = camera.SetExposure(exposure);
    camera.SetNextFrameIndex(kMeterFrameIndex + attempt);
    const Frame f = camera.Grab(std::chrono::milliseconds(10000));
    std::vector<float> signal;
    for (size_t i = 0; i < f.data.size(); ++i) {
      if (c.CameraValid(static_cast<int>(i))) signal.push_back(static_cast<float>(f.data[i] - c.black_dn));
    }
    if (signal.empty()) throw DeviceError("metering: the camera sees no valid pixel");
    const size_t q = signal.size() * 999 / 1000;
    std::nth_element(signal.begin(), signal.begin() + q, signal.end());
    const double p999 = signal[q];
    if (p999 >= 0.9 * range) {
      exposure /= 16;  // saturated: much shorter
    } else if (p999 < 0.02 * range) {
      exposure *= 16;  // too dark to measure well
    } else {
      return std::clamp(exposure * 0.7 * range / p999, info.min_exposure_us, info.max_exposure_us);
    }
    if (exposure < info.min_exposure_us || exposure > info.max_exposure_us) break;
    exposure = std::clamp(exposure, info.min_exposure_us, info.max_exposure_us);
  }
  throw DeviceError("metering failed: no exposure within the camera's limits brings the white "
                    "pattern into the sensor's range; check the projector and the lens cap");
}

void CaptureJobOptions::Validate() const {
  OptionChecker check("CaptureJobOptions");
  check.Require(!out_dir.empty(), "out_dir", "must name the session folder (--out)")
      .InRange("order", order, 0, 30);
  if (zone_min_deg >= 0 && zone_max_deg > 0) {
    check.ValidZone("zone_min_deg, zone_max_deg", DegToRad(zone_min_deg), DegToRad(zone_max_deg));
  }
  // An adaptive capture decides its own bracket (acquisition/adaptive.h).
  if (!(adaptive.enabled && adaptive.adaptive_exposures)) {
    check.InRange("exposures", exposures, 1, 10).InRangeAbove("stops_apart", stops_apart, 0, 8);
  }
  check.Require(shortest_exposure_us >= 0 && std::isfinite(shortest_exposure_us),
                "shortest_exposure_us",
                "must be > 0, or 0 to meter it (got " + FormatOptionValue(shortest_exposure_us) +
                    ")")
      .InRange("repeats", repeats, 1, 100)
      .Nested("processing", processing);
  if (adaptive.enabled) check.Nested("adaptive", adaptive);
  check.Require(!(resume && force_new), "resume, force_new",
                "--resume continues the session in --out, --force-new starts a new one there: "
                "give one of them");
  check.ThrowIfInvalid();
}

namespace {

// The session's plan from its session.json, naming the file in any error.
CapturePlan SessionPlan(const SessionFolder& session) {
  const std::string where = SessionPath(session.path(), kSessionFile) + " plan";
  if (!session.session().contains("plan")) {
    throw InputError(SessionPath(session.path(), kSessionFile) +
                     " has no plan; the session folder is damaged");
  }
  return CapturePlan::FromJson(session.session().at("plan"), where);
}

// A writer lock that someone else holds, found before any setup: SessionBusyError.
void CheckNobodyWrites(const std::string& dir) {
  std::error_code error;
  if (!std::filesystem::exists(SessionPath(dir, kLockFile), error)) return;
  std::shared_ptr<SessionLock> probe = SessionLock::Acquire(dir);  // throws if held elsewhere
}

}  // namespace

void CheckCaptureJob(const CaptureJobOptions& options) {
  options.Validate();
  if (options.resume) {
    const SessionFolder session = SessionFolder::Open(options.out_dir);
    const CapturePlan plan = SessionPlan(session);
    CheckExitantGrid(plan.zone(), plan.order, options.processing.theta_step_deg,
                     options.processing.phi_step_deg);
  } else if (!options.force_new) {
    CheckNewSessionFolder(options.out_dir);
  }
  CheckNobodyWrites(options.out_dir);
}

CapturePlan CheckProcessSession(const std::string& session_dir, const ProcessingOptions& options) {
  options.Validate();
  const SessionFolder session = SessionFolder::Open(session_dir);
  const CapturePlan plan = SessionPlan(session);
  CheckExitantGrid(plan.zone(), plan.order, options.theta_step_deg, options.phi_step_deg);
  CheckNobodyWrites(session_dir);
  return plan;
}

namespace {

CaptureJobResult RunCaptureJobUnguarded(const Rig& rig, const RigCalibration& calibration,
                                        Camera& camera, Projector& projector, Clock& clock,
                                        const CaptureJobOptions& options);

}  // namespace

CaptureJobResult RunCaptureJob(const Rig& rig, const RigCalibration& calibration, Camera& camera,
                               Projector& projector, Clock& clock,
                               const CaptureJobOptions& options) {
  try {
    return RunCaptureJobUnguarded(rig, calibration, camera, projector, clock, options);
  } catch (const FileWriteError& e) {
    // What to do once the disk has room again: whatever was journaled is kept.
    if (SessionFolder::Exists(options.out_dir)) {
      throw e.WithNextStep(
          "continue with the same command plus --resume (every frame "
          "journaled so far is kept)");
    }
    throw e.WithNextStep("run the same command again");
  }
}

namespace {

CaptureJobResult RunCaptureJobUnguarded(const Rig& rig, const RigCalibration& calibration,
                                        Camera& camera, Projector& projector, Clock& clock,
                                        const CaptureJobOptions& options) {
  CheckCaptureJob(options);
  CaptureJobResult result;
  const double settle_us =
      options.settle_us >= 0 ? options.settle_us : rig.timing.projector_settle_ms * 1e3;
  std::optional<SessionFolder> opened;
  PlanOptions po;
  if (options.resume) {
    opened = SessionFolder::OpenForWriting(options.out_dir);
    result.plan = SessionPlan(*opened);
    if (opened->session().value("rig_hash", std::string()) != std::to_string(RigHash(rig))) {
      throw InputError("session " + options.out_dir + " was captured with another rig "
                       "description; resume it with the same --rig and --preset (and, for "
                       "zbrdf simulate, --samples-per-pixel)");
    }
    result.repairs = opened->repairs();
  } else {
    // Everything is validated before the folder is created: a refused job leaves no trace.
    double covered_lo, covered_hi;
    calibration.CoveredThetaRange(&covered_lo, &covered_hi);
    if (options.zone_min_deg >= 0 && options.zone_max_deg > 0) {
      po.theta_min_rad = DegToRad(options.zone_min_deg);
      po.theta_max_rad = DegToRad(options.zone_max_deg);
      if (po.theta_min_rad < covered_lo - 1e-9 || po.theta_max_rad > covered_hi + 1e-9) {
        throw InputError("zone [" + std::to_string(options.zone_min_deg) + ", " +
                         std::to_string(options.zone_max_deg) + "] deg is not inside what the rig covers (" +
                         std::to_string(RadToDeg(covered_lo)) + " to " +
                         std::to_string(RadToDeg(covered_hi)) + " deg)");
      }
    } else {
      // Projector pixels at the rims of the mirrors are partly vignetted and their footprints
      // are known less well: keep the zone 1.5 projector pixels (at least 0.2 deg) inside.
      const double pixel = std::max(calibration.ProjectorPixelSizeRad(covered_lo),
                                    calibration.ProjectorPixelSizeRad(covered_hi));
      DefaultZone(covered_lo, covered_hi, std::max(0.2, 1.5 * RadToDeg(pixel)), &po.theta_min_rad,
                  &po.theta_max_rad);
    }
    po.order = options.order;
    po.exposures = options.exposures;
    po.stops_apart = options.stops_apart;
    if (options.adaptive.enabled) {
      if (options.adaptive.adaptive_exposures) {
        // The metered frame, then one as long as the pattern's response allows.
        po.exposures = options.adaptive.max_ratio > 1 ? 2 : 1;
        po.stops_apart = options.adaptive.max_ratio > 1 ? std::log2(options.adaptive.max_ratio) : 2;
      }
    }
    po.repeats = options.repeats;
    po.shortest_exposure_us = options.shortest_exposure_us > 0 ? options.shortest_exposure_us : 1000;
    // Validates the options, and the exitant grid against the zone and order, before metering.
    CheckExitantGrid(Zone(po.theta_min_rad, po.theta_max_rad), po.order,
                     options.processing.theta_step_deg, options.processing.phi_step_deg);
    MakePlan(po);
    result.metered_exposure_us = options.shortest_exposure_us > 0
                                     ? options.shortest_exposure_us
                                     : MeterExposure(camera, projector, clock, calibration, settle_us);
    po.shortest_exposure_us = result.metered_exposure_us;
    if (options.shortest_exposure_us <= 0) {
      // A dark sample meters a long exposure; the bracket's longest frame must still fit the
      // camera, so the metered bracket is shifted down to end at the camera's limit.
      const CameraInfo limits = camera.Info();
      const double span = std::pow(2.0, po.stops_apart * (po.exposures - 1));
      if (limits.max_exposure_us > 0 && po.shortest_exposure_us * span > limits.max_exposure_us) {
        po.shortest_exposure_us =
            std::max(limits.min_exposure_us, limits.max_exposure_us / span);
        result.metered_exposure_us = po.shortest_exposure_us;
      }
    }
    result.plan = MakePlan(po);
    nlohmann::json info = options.session_extra.is_object() ? options.session_extra : nlohmann::json::object();
    info["software"] = {{"name", "zbrdf"}, {"version", ZBRDF_VERSION_STRING}};
    info["rig"] = WriteRigYaml(rig);
    info["rig_name"] = rig.name;
    info["rig_source"] = rig.source_path;
    info["rig_hash"] = std::to_string(RigHash(rig));
    info["calibration"] = calibration.source;
    info["plan"] = result.plan.ToJson();
    if (options.adaptive.enabled) {
      info["adaptive"] = {{"options", options.adaptive.ToJson()}, {"state", "running"}};
    }
    const CameraInfo ci = camera.Info();
    const ProjectorInfo pi = projector.Info();
    info["devices"] = {{"camera", {{"id", ci.id}, {"model", ci.model}, {"width", ci.width},
                                   {"height", ci.height}, {"layout", PixelLayoutName(ci.layout)},
                                   {"bit_depth", ci.bit_depth}}},
                       {"projector", {{"id", pi.id}, {"model", pi.model}, {"width", pi.width},
                                      {"height", pi.height}, {"bit_depth", pi.bit_depth}}}};
    if (options.force_new) result.moved_aside = MoveSessionFolderAside(options.out_dir);
    opened = SessionFolder::Create(options.out_dir, info);
  }
  SessionFolder& session = *opened;
  result.lock = session.lock();
  result.predicted_capture_time_s = PredictCaptureTimeS(result.plan, rig.timing);
  if (options.on_plan) options.on_plan(result.plan, result.predicted_capture_time_s);

  const auto pattern_start = std::chrono::steady_clock::now();
  const PatternSet patterns(result.plan, calibration,
                            options.pattern_cache_dir.empty() ? DefaultCacheDir() : options.pattern_cache_dir,
                            options.progress);
  result.pattern_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - pattern_start).count();

  ProcessingOptions processing = options.processing;
  processing.hdr_folder = SessionPath(session.path(), kHdrFolder);
  ZonalProcessor processor(result.plan, patterns.lobes(), calibration, processing);
  processor.Start();
  CaptureOptions capture;
  capture.settle_us = settle_us;
  capture.progress = options.progress;
  capture.interrupt = options.interrupt;
  capture.on_lobe_complete = [&](int lobe, const std::vector<Frame>& frames) {
    processor.AddLobe(lobe, frames);
  };
  // An adaptive session keeps deciding as it did when it was created (also on resume); once its
  // order is settled ("state": "done") only the exposure rule remains, for recaptured frames.
  std::unique_ptr<AdaptiveController> adaptive;
  bool adaptive_running = false;
  if (session.session().contains("adaptive")) {
    const nlohmann::json& a = session.session()["adaptive"];
    adaptive = std::make_unique<AdaptiveController>(
        result.plan, calibration, AdaptiveOptions::FromJson(a.at("options")), &processor);
    adaptive_running = a.value("state", std::string()) == "running";
    capture.exposure_us = [&](int lobe, int exposure, const std::vector<const Frame*>& shorter) {
      return adaptive->ExposureUs(lobe, exposure, shorter);
    };
    if (adaptive_running) {
      capture.stop_after_lobe = [&](int lobe) { return adaptive->StopAfterLobe(lobe); };
      capture.skip_lobe = [&](int lobe) { return adaptive->SkipLobe(lobe); };
      capture.skip_lobe_ahead = [&](int lobe) { return adaptive->WouldSkipLobe(lobe); };
    }
  }
  const std::set<std::string> skipped = SkippedLobes(session.session());
  if (!skipped.empty()) {
    capture.skip_lobe = [&](int lobe) { return skipped.count(result.plan.lobes[lobe].Name()) > 0; };
    capture.skip_lobe_ahead = capture.skip_lobe;
  }
  const auto capture_start = std::chrono::steady_clock::now();
  result.capture = RunCapture(session, result.plan, patterns, camera, projector, clock, capture);
  const auto last_frame = std::chrono::steady_clock::now();
  result.wall_capture_s = std::chrono::duration<double>(last_frame - capture_start).count();
  if (result.capture.interrupted) return result;
  const int order = adaptive ? adaptive->order() : result.plan.order;
  result.zonal = processor.Finish(order);
  result.processing = processor.stats();
  if (adaptive_running) {
    result.adaptive = adaptive->Report();
    nlohmann::json info = session.session();
    const CapturePlan kept = TruncatePlan(result.plan, order);
    info["plan"] = kept.ToJson();
    info["adaptive"] = result.adaptive;
    info["adaptive"]["state"] = "done";
    session.UpdateSession(info);
    result.plan = kept;
  } else if (adaptive) {
    result.adaptive = session.session()["adaptive"];
  }
  result.zonal.attributes = {{"rig", rig.name},
                             {"rig_hash", std::to_string(RigHash(rig))},
                             {"calibration", calibration.source},
                             {"session", session.path()},
                             {"units", "z_k(w_r) = integral Z_k(w_i) f_r(w_i,w_r) cos(theta_i) dw_i "
                                       "[sr^-1/2]; tensor z_kj = integral z_k Z_j dw_r"}};
  for (const char* key : {"material", "seed", "preset"}) {
    if (session.session().contains(key)) result.zonal.attributes[key] = session.session()[key];
  }
  WriteZonalExr(SessionPath(session.path(), kZonalFile), result.zonal);
  result.ready_after_last_frame_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last_frame).count();
  processor.WaitForImages();
  result.processing = processor.stats();
  result.complete = true;
  return result;
}

ProcessResult ProcessSessionUnguarded(const std::string& session_dir,
                                      const RigCalibration& calibration,
                                      const ProcessingOptions& options,
                                      const std::string& pattern_cache_dir,
                                      const ProgressCallback& progress) {
  CheckProcessSession(session_dir, options);
  const SessionFolder session = SessionFolder::OpenForWriting(session_dir);
  ProcessResult result;
  result.lock = session.lock();
  result.repairs = session.repairs();
  result.plan = SessionPlan(session);
  const PatternSet patterns(result.plan, calibration,
                            pattern_cache_dir.empty() ? DefaultCacheDir() : pattern_cache_dir,
                            progress);
  std::map<int, JournalEntry> journal;
  // An adaptive session decides its exposures (all but a bracket's first) while it captures.
  const nlohmann::json& info = session.session();
  const bool adaptive_exposures =
      info.contains("adaptive") && info["adaptive"].is_object() &&
      info["adaptive"].contains("options") &&
      AdaptiveOptions::FromJson(info["adaptive"]["options"]).adaptive_exposures;
  for (JournalEntry& e : session.ReadJournal()) {
    if (e.index >= result.plan.frame_count()) continue;  // an adaptive session's dropped bands
    const std::string mismatch =
        JournalEntryMismatch(e, result.plan, session.session_id(), !adaptive_exposures);
    if (!mismatch.empty()) {
      throw InputError("session " + session_dir + ": " + mismatch +
                       "; the journal does not belong to this session or is damaged: resume the "
                       "capture (--resume) to take the frame again");
    }
    journal[e.index] = std::move(e);
  }
  ProcessingOptions processing = options;
  processing.hdr_folder = SessionPath(session_dir, kHdrFolder);
  ZonalProcessor processor(result.plan, patterns.lobes(), calibration, processing);
  processor.Start();
  const int per_lobe = static_cast<int>(result.plan.exposures_us.size()) * result.plan.repeats;
  const std::set<std::string> skipped = SkippedLobes(session.session());
  const auto start = std::chrono::steady_clock::now();
  // Frames are read and verified on this thread while the processor merges the previous lobe.
  for (int lobe = 0; lobe < static_cast<int>(result.plan.lobes.size()); ++lobe) {
    if (skipped.count(result.plan.lobes[lobe].Name())) {
      processor.AddLobe(lobe, {});  // synthesized (isotropy)
      continue;
    }
    std::vector<Frame> frames;
    for (int k = 0; k < per_lobe; ++k) {
      const int index = lobe * per_lobe + k;
      const auto it = journal.find(index);
      if (it == journal.end()) {
        throw InputError("session " + session_dir + " lacks frame " + std::to_string(index) + " (" +
                         result.plan.lobes[lobe].Name() +
                         "); the capture was interrupted: resume it with --resume");
      }
      frames.push_back(session.ReadFrame(it->second));
    }
    processor.AddLobe(lobe, std::move(frames));
    Report(progress, {"process", lobe + 1, static_cast<long>(result.plan.lobes.size()), "patterns"});
  }
  result.read_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.zonal = processor.Finish();
  result.processing = processor.stats();
  result.zonal.attributes = {{"rig", session.session().value("rig_name", std::string())},
                             {"rig_hash", session.session().value("rig_hash", std::string())},
                             {"calibration", calibration.source},
                             {"session", session_dir},
                             {"units", "z_k(w_r) = integral Z_k(w_i) f_r(w_i,w_r) cos(theta_i) dw_i "
                                       "[sr^-1/2]; tensor z_kj = integral z_k Z_j dw_r"}};
  for (const char* key : {"material", "seed", "preset"}) {
    if (session.session().contains(key)) result.zonal.attributes[key] = session.session()[key];
  }
  WriteZonalExr(SessionPath(session_dir, kZonalFile), result.zonal);
  processor.WaitForImages();
  result.processing = processor.stats();
  return result;
}

}  // namespace

ProcessResult ProcessSession(const std::string& session_dir, const RigCalibration& calibration,
                             const ProcessingOptions& options, const std::string& pattern_cache_dir,
                             const ProgressCallback& progress) {
  try {
    return ProcessSessionUnguarded(session_dir, calibration, options, pattern_cache_dir, progress);
  } catch (const FileWriteError& e) {
    throw e.WithNextStep("run zbrdf process " + session_dir +
                         " again (the previous zonal.exr and HDR images are untouched)");
  }
}

}  // namespace zbrdf
