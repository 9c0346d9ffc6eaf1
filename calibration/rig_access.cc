#include "calibration/rig_access.h"

#include "acquisition/capture_job.h"
#include "basis/error.h"

namespace zbrdf {

std::string TargetDescription(Target target) {
  switch (target) {
    case Target::kWhite: return "white target";
    case Target::kMirror: return "flat mirror";
    case Target::kGrayCard: return "18% gray card";
  }
  return "?";
}

std::string TargetMaterialSpec(Target target) {
  switch (target) {
    case Target::kWhite: return "target:white";
    case Target::kMirror: return "target:mirror";
    case Target::kGrayCard: return "target:graycard";
  }
  return "";
}

Pattern UniformPattern(const RigCalibration& c, int level) {
  Pattern p;
  p.width = c.projector_width;
  p.height = c.projector_height;
  p.bit_depth = c.projector_bit_depth;
  p.levels.assign(static_cast<size_t>(p.width) * p.height, static_cast<uint16_t>(level));
  return p;
}

void ShowPattern(CalibrationRig& rig, const Pattern& pattern) {
  rig.projector->Show(pattern);
  rig.clock->SleepUs(static_cast<int64_t>(rig.settle_us));
}

Frame TakeFrame(CalibrationRig& rig, double exposure_us) {
  const double used = rig.camera->SetExposure(exposure_us);
  (void)used;
  rig.camera->SetNextFrameIndex(rig.next_frame_index++);
  return rig.camera->Grab(std::chrono::milliseconds(10000));
}

HdrImage TakeHdr(CalibrationRig& rig, const RigCalibration& calibration,
                 const std::vector<double>& exposures_us, const std::string& what) {
  std::vector<Frame> frames;
  for (double t : exposures_us) frames.push_back(TakeFrame(rig, t));
  return MergeExposures(frames, calibration, what);
}

double MeterWhite(CalibrationRig& rig, const RigCalibration& calibration) {
  const uint64_t index = rig.next_frame_index;
  rig.next_frame_index += 16;
  // MeterExposure keys its frames itself; give it a camera view of our index range.
  class IndexedCamera final : public Camera {
   public:
    IndexedCamera(Camera& inner, uint64_t base) : inner_(inner), base_(base) {}
    CameraInfo Info() const override { return inner_.Info(); }
    double SetExposure(double us) override { return inner_.SetExposure(us); }
    void SetTriggerMode(TriggerMode mode) override { inner_.SetTriggerMode(mode); }
    void SetNextFrameIndex(uint64_t) override { inner_.SetNextFrameIndex(base_ + count_++); }
    Frame Grab(std::chrono::milliseconds timeout) override { return inner_.Grab(timeout); }

   private:
    Camera& inner_;
    uint64_t base_, count_ = 0;
  } camera(*rig.camera, index);
  return MeterExposure(camera, *rig.projector, *rig.clock, calibration, rig.settle_us);
}

RateImage Subtract(const HdrImage& lit, const HdrImage& dark) {
  if (lit.rate.size() != dark.rate.size()) {
    throw InternalError("Subtract: HDR images of different sizes");
  }
  RateImage out;
  out.width = lit.width;
  out.height = lit.height;
  out.layout = lit.layout;
  out.rate.assign(lit.rate.size(), 0.0f);
  out.valid.assign(lit.rate.size(), 0);
  for (size_t i = 0; i < lit.rate.size(); ++i) {
    if (!lit.valid[i] || !dark.valid[i]) continue;
    out.rate[i] = lit.rate[i] - dark.rate[i];
    out.valid[i] = 1;
  }
  return out;
}

}  // namespace zbrdf
