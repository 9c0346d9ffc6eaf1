// What a calibration step drives: the camera and projector (hardware or the virtual rig), and
// the targets it needs placed as the sample. Shared helpers to show patterns and take frames
// and HDR images.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "acquisition/hdr.h"
#include "acquisition/rig_calibration.h"
#include "basis/progress.h"
#include "drivers/camera.h"
#include "drivers/clock.h"
#include "drivers/projector.h"

namespace zbrdf {

enum class Target { kWhite, kMirror, kGrayCard };
// "white target", "flat mirror", "18% gray card"
std::string TargetDescription(Target target);
// The simulator's material for the target: "target:white", "target:mirror", "target:graycard".
std::string TargetMaterialSpec(Target target);

// Calibration frames get frame indices of their own (the virtual camera keys its noise on
// them), far from any capture plan's and from exposure metering's.
inline constexpr uint64_t kCalibrationFrameBase = 1ull << 42;

struct CalibrationRig {
  Camera* camera = nullptr;
  Projector* projector = nullptr;
  Clock* clock = nullptr;
  double settle_us = 0;  // after a new pattern
  // Puts the target in the sample position: the virtual rig swaps its material; on hardware the
  // user is asked to place it. Called before each step that needs one.
  std::function<void(Target)> place_target;
  ProgressCallback progress;
  uint64_t next_frame_index = kCalibrationFrameBase;
};

// A full-screen pattern of one level.
Pattern UniformPattern(const RigCalibration& calibration, int level);
// Shows the pattern and waits the settle time.
void ShowPattern(CalibrationRig& rig, const Pattern& pattern);
// One frame of whatever is shown. Throws DeviceError from the camera.
Frame TakeFrame(CalibrationRig& rig, double exposure_us);
// The HDR merge of one frame per exposure of whatever is shown (acquisition/hdr.h).
HdrImage TakeHdr(CalibrationRig& rig, const RigCalibration& calibration,
                 const std::vector<double>& exposures_us, const std::string& what);
// Shortest exposure that puts the brightest pixels of a full-white pattern at 70% of the range
// (acquisition's MeterExposure).
double MeterWhite(CalibrationRig& rig, const RigCalibration& calibration);

// Per camera pixel, HDR rate minus the dark image's, 0 where either is invalid (and valid = 0).
struct RateImage {
  int width = 0, height = 0;
  PixelLayout layout = PixelLayout::kMono;
  std::vector<float> rate;
  std::vector<uint8_t> valid;
};
RateImage Subtract(const HdrImage& lit, const HdrImage& dark);

}  // namespace zbrdf
