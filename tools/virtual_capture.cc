#include "tools/virtual_capture.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

#include "acquisition/processing.h"
#include "acquisition/rig_calibration.h"
#include "acquisition/session.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "brdf/material_spec.h"
#include "calibration/calibration_data.h"
#include "drivers/aravis_camera.h"
#include "drivers/fake_gige_camera.h"
#include "rig/direction_maps.h"
#include "simulate/virtual_rig.h"

namespace zbrdf {
namespace {

// The GenICam pixel format a camera with this sensor would stream, among those the fake offers.
std::string GigEPixelFormat(PixelLayout layout, int bit_depth) {
  if (layout == PixelLayout::kMono && bit_depth == 12) return "Mono12";
  if (layout == PixelLayout::kMono && bit_depth == 16) return "Mono16";
  if (layout == PixelLayout::kBayerRGGB && bit_depth == 12) return "BayerRG12";
  if (layout == PixelLayout::kBayerRGGB && bit_depth == 16) return "BayerRG16";
  if (layout == PixelLayout::kBayerGBRG && bit_depth == 16) return "BayerGB16";
  throw InputError("the GigE Vision fake camera offers no pixel format for a " +
                   PixelLayoutName(layout) + " " + std::to_string(bit_depth) +
                   "-bit sensor; use mono or bayer-rggb with 12 or 16 bits, or capture without "
                   "--gige-fake");
}

// The virtual camera behind an Aravis fake GigE Vision camera on 127.0.0.1: the session talks to
// the AravisCamera driver; the fake fills each triggered frame from the virtual camera, with the
// plan's frame index forwarded so noise realizations match the direct link. A frame the driver
// drops for missing packets is filled again with the same index, so it comes out identical.
class GigEFakeLink {
 public:
  GigEFakeLink(VirtualRig& rig, const GigEFakeOptions& options) : rig_(rig), options_(options) {
    const CameraInfo info = rig.camera().Info();
    FakeGigECameraOptions fake_options;
    fake_options.serial = "ZBRDF-VIRTUAL";
    fake_ = std::make_unique<FakeGigECamera>(fake_options);
    fake_->SetLostPacketRatio(options.lost_packet_ratio, /*seed=*/1);
    fake_->SetFrameSource([this](const FakeFrameRequest& request, std::vector<uint16_t>* samples) {
      Fill(request, samples);
    });
    AravisCameraOptions camera;
    camera.ip = FakeGigECamera::kAddress;
    camera.pixel_format = GigEPixelFormat(info.layout, info.bit_depth);
    camera.region_width = info.width;
    camera.region_height = info.height;
    camera.exposure_min_us = info.min_exposure_us;
    camera.exposure_max_us = info.max_exposure_us;
    // Aravis's fake camera answers no packet resend, so a frame it dropped a packet of is
    // captured again: as many attempts as make a frame fail for good with probability below
    // 1e-9 at the loss asked for (at least the usual 6). The packets are counted at 1000 bytes
    // (the fake's are larger: fewer packets, so this errs towards more attempts). At 0.002 and
    // the fast preset, 134 packets a frame, 23% of frames lose one: 15 attempts; 6 fail once in
    // 6000-35000 frames, and did fail one CI run.
    const double packets = std::ceil(static_cast<double>(info.width) * info.height *
                                     (info.bit_depth > 8 ? 2 : 1) / 1000.0) +
                           2;
    const double incomplete = 1 - std::pow(1 - options.lost_packet_ratio, packets);
    camera.retries = 5;
    if (incomplete > 0 && incomplete < 1) {
      camera.retries = std::clamp(
          static_cast<int>(std::ceil(std::log(1e-9) / std::log(incomplete))) - 1, 5, 100);
    } else if (incomplete >= 1) {
      camera.retries = 100;
    }
    // The fake is a thread of this process on loopback: a frame's packets come late only when
    // the machine is too busy to run its sender, never from the link, and Aravis's default (a
    // frame kept 100 ms for its packets) then drops frames that would complete; under a
    // parallel multi-process test six in a row did (CI, twice). 300 ms: a frame the fake
    // deliberately broke (lost_packet_ratio) is also kept that long before it is captured
    // again, which at 1 s made the lossy test 5x slower.
    camera.frame_retention_us = 300'000;
    driver_ = std::make_unique<AravisCamera>(camera, &rig.clock());
    forwarding_ = std::make_unique<Forwarding>(*this);
  }

  Camera& camera() { return *forwarding_; }
  uint64_t incomplete_frames() const { return driver_->Stats().incomplete_frames; }

 private:
  // What the session sees: the driver, plus the plan's frame index for the fake's fills.
  class Forwarding final : public Camera {
   public:
    explicit Forwarding(GigEFakeLink& link) : link_(link) {}
    CameraInfo Info() const override { return link_.driver_->Info(); }
    // The virtual sensor quantizes exposure to 1 us; ask the camera for exactly that.
    double SetExposure(double exposure_us) override {
      return link_.driver_->SetExposure(std::round(exposure_us));
    }
    void SetTriggerMode(TriggerMode mode) override { link_.driver_->SetTriggerMode(mode); }
    void SetNextFrameIndex(uint64_t index) override {
      std::lock_guard<std::mutex> lock(link_.mutex_);
      link_.next_index_ = index;
    }
    Frame Grab(std::chrono::milliseconds timeout) override {
      if (link_.options_.stop_after_frames > 0 &&
          link_.grabbed_ >= link_.options_.stop_after_frames) {
        link_.fake_->Stop();  // as if the camera lost power; the driver notices and says so
      }
      Frame frame = link_.driver_->Grab(timeout);
      std::lock_guard<std::mutex> lock(link_.mutex_);
      ++link_.next_index_;
      ++link_.grabbed_;
      return frame;
    }

   private:
    GigEFakeLink& link_;
  };

  // On the fake's thread, while the session waits in Grab.
  void Fill(const FakeFrameRequest& request, std::vector<uint16_t>* samples) {
    std::lock_guard<std::mutex> lock(mutex_);
    Camera& source = rig_.camera();
    source.SetExposure(request.exposure_us);
    source.SetNextFrameIndex(next_index_);
    Frame frame = source.Grab(std::chrono::milliseconds(1000));
    if (frame.width != request.width || frame.height != request.height ||
        frame.bit_depth != request.bit_depth) {
      throw DeviceError("the fake camera streams " + std::to_string(request.width) + "x" +
                        std::to_string(request.height) + " " + request.pixel_format +
                        ", the virtual sensor makes " + std::to_string(frame.width) + "x" +
                        std::to_string(frame.height) + " at " + std::to_string(frame.bit_depth) +
                        " bits");
    }
    *samples = std::move(frame.data);
  }

  VirtualRig& rig_;
  GigEFakeOptions options_;
  std::mutex mutex_;
  uint64_t next_index_ = 0;
  int grabbed_ = 0;
  std::unique_ptr<FakeGigECamera> fake_;
  std::unique_ptr<AravisCamera> driver_;
  std::unique_ptr<Forwarding> forwarding_;
};

}  // namespace

void GigEFakeOptions::Validate() const {
  OptionChecker check("GigEFakeOptions");
  check.InRange("lost_packet_ratio", lost_packet_ratio, 0, 1)
      .AtLeast("stop_after_frames", stop_after_frames, 0)
      .ThrowIfInvalid();
}

VirtualCaptureOutcome RunVirtualCapture(VirtualCaptureArgs args) {
  const auto start = std::chrono::steady_clock::now();
  args.gige.Validate();
  // Options, the folder's state and its writer, before the (slow) virtual rig is built.
  CheckCaptureJob(args.job);
  if (args.job.resume) {
    // The session decides what is being captured.
    const nlohmann::json s = SessionFolder::Open(args.job.out_dir).session();
    const std::string material = s.value("material", std::string());
    if (material.empty()) {
      throw InputError("session " + args.job.out_dir +
                       " was not captured on the virtual rig "
                       "(no material in session.json); resume it with its hardware rig file");
    }
    if (!args.material_spec.empty() && MakeBrdf(args.material_spec)->Spec() != material) {
      throw InputError("session " + args.job.out_dir + " captures " + material + ", not " +
                       args.material_spec + "; leave --material out to resume it");
    }
    args.material_spec = material;
    args.seed = s.value("seed", args.seed);
    args.noise = s.value("noise", args.noise);
    args.faults_yaml = s.value("faults", std::string());
    args.faults_name = "session faults";
    // The link is how frames travel, not what they are: a session may resume over either.
    if (args.calibration_folder.empty())
      args.calibration_folder = s.value("calibration_folder", std::string());
  }
  if (args.material_spec.empty()) throw InputError("no --material given for the virtual rig");
  VirtualCaptureOutcome out;
  out.material = MakeBrdf(args.material_spec);
  VirtualRig::Options vr;
  vr.seed = args.seed;
  vr.noise = args.noise;
  vr.progress = args.job.progress;
  const Rig as_built = args.faults_yaml.empty()
                           ? args.rig
                           : ApplyRigOverlayText(args.rig, args.faults_yaml, args.faults_name);
  VirtualRig rig(as_built, out.material, vr);
  out.transport_entries = rig.model().transport_entries();
  // Without a calibration folder or faults the rig as built is the design, whose maps the
  // virtual rig holds already: the nominal calibration is derived from them rather than from
  // the maps' cache entry read back (0.4 s at full resolution, between the transport and the
  // capture).
  const RigCalibration calibration = args.calibration_folder.empty() && args.faults_yaml.empty()
                                         ? NominalCalibration(args.rig, rig.maps())
                                         : LoadRigCalibration(args.rig, args.calibration_folder,
                                                              DefaultCacheDir(), args.job.progress);
  out.setup_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  args.job.session_extra = {{"material", out.material->Spec()},
                            {"seed", args.seed},
                            {"preset", args.preset_name},
                            {"noise", args.noise},
                            {"kind", "simulated"}};
  if (!args.faults_yaml.empty()) args.job.session_extra["faults"] = args.faults_yaml;
  std::unique_ptr<GigEFakeLink> gige;
  Camera* camera = &rig.camera();
  if (args.camera_link == CameraLink::kGigEFake) {
    gige = std::make_unique<GigEFakeLink>(rig, args.gige);
    camera = &gige->camera();
    args.job.session_extra["camera_link"] = "gige-fake";
  }
  if (!args.calibration_folder.empty()) {
    args.job.session_extra["calibration_folder"] =
        std::filesystem::absolute(args.calibration_folder).lexically_normal().string();
  }
  if (args.on_plan_material) {
    args.job.on_plan = [user = args.job.on_plan, hook = args.on_plan_material,
                        material = out.material](const CapturePlan& plan, double predicted_s) {
      if (user) user(plan, predicted_s);
      hook(plan, material);
    };
  }
  out.result =
      RunCaptureJob(args.rig, calibration, *camera, rig.projector(), rig.clock(), args.job);
  if (gige) out.incomplete_frames = gige->incomplete_frames();
  out.device_time_s = rig.clock().NowUs() * 1e-6;
  return out;
}

Rig SessionRig(const std::string& session_dir) {
  const nlohmann::json s = SessionFolder::Open(session_dir).session();
  if (!s.contains("rig") || !s["rig"].is_string()) {
    throw InputError(session_dir + "/session.json has no rig description; the session is damaged");
  }
  return ParseRig(s["rig"].get<std::string>(), session_dir + "/session.json (rig)");
}

}  // namespace zbrdf

namespace zbrdf {

std::string ReadTextFile(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw InputError(what + " " + path + " cannot be read");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string SessionCalibrationFolder(const std::string& session_dir) {
  return SessionFolder::Open(session_dir).session().value("calibration_folder", std::string());
}

namespace {

// Whether the true coefficients integrated for `a` hold for `b`: the same zone, order and grid.
bool SameLayout(const ZonalData& a, const ZonalData& b) {
  const ExitantGrid &g = a.grid, &h = b.grid;
  return a.theta_min_rad == b.theta_min_rad && a.theta_max_rad == b.theta_max_rad &&
         a.order == b.order && g.theta_min_rad == h.theta_min_rad &&
         g.theta_max_rad == h.theta_max_rad && g.theta_step_rad == h.theta_step_rad &&
         g.phi_step_rad == h.phi_step_rad && g.n_theta == h.n_theta && g.n_phi == h.n_phi;
}

}  // namespace

void EarlyTruth::StartAtPlan(VirtualCaptureArgs* args) {
  args->on_plan_material = [this, processing = args->job.processing](
                               const CapturePlan& plan,
                               const std::shared_ptr<const Brdf>& material) {
    layout_ = ZonalLayout(plan, processing);
    early_ = std::async(std::launch::async,
                        [material, layout = layout_, options = options_, cache = cache_dir_] {
                          return TrueZonalCoefficientsCached(*material, layout, options, cache);
                        });
  };
}

GroundTruth EarlyTruth::Get(const Brdf& material, const ZonalData& zonal) {
  if (early_.valid() && SameLayout(layout_, zonal)) return early_.get();
  return TrueZonalCoefficientsCached(material, zonal, options_, cache_dir_);
}

}  // namespace zbrdf
