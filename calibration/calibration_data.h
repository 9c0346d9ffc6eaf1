// A rig calibration: what `zbrdf calibrate` measured, kept in a calibration folder that
// sessions reference and `zbrdf process` applies (docs/calibration.md).
//
//   calibration.json      the design rig it belongs to (name and hash) and, per step, its
//                         results and report
//   correspondences.exr   gray code through the mirror target: per camera pixel the projector
//                         pixel it sees (channels u, v; -1 where none)
//   projector_flat.exr    projector flat field (channel Y), per projector pixel
//   camera_flat.exr       camera flat field (channel Y), per camera pixel
//   *.png                 a figure per step
//   graycard-session/     the gray-card capture session
//
// The steps build on each other in this order, each using what the earlier ones found:
// geometry (misalignment of camera and projector against the mirrors), noise (EMVA 1288
// sensor parameters), projector (response curve and flat field), gray card (camera flat field
// and per-channel scale). Any subset may be present; what is missing stays nominal.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "acquisition/rig_calibration.h"
#include "basis/progress.h"
#include "rig/rig.h"

namespace zbrdf {

struct SensorCalibration {
  double gain_e_per_dn = 0;
  double read_noise_e = 0;
  double black_dn = 0;
  double saturation_dn = 0;
};

struct ProjectorResponseCalibration {
  std::vector<double> response;  // normalized output (black removed) per level, 0 .. 1
  double black_fraction = 0;     // level-0 output over the full range
};

// A per-pixel factor (flat field), width x height, row-major.
struct PixelField {
  int width = 0, height = 0;
  std::vector<float> value;
};

struct CalibrationData {
  std::string rig_name, rig_hash;            // the design rig (preset applied)
  std::optional<Misalignment> misalignment;  // geometry step
  std::optional<SensorCalibration> sensor;   // noise step
  std::optional<ProjectorResponseCalibration> projector_response;  // projector step
  std::optional<PixelField> projector_flat;  // projector step
  std::optional<PixelField> camera_flat;     // projector step (white target), gray-card step
  std::string camera_flat_source;            // "white target" or "gray card"
  std::optional<std::array<double, 3>> scale_rgb;  // gray-card step
  nlohmann::json reports = nlohmann::json::object();  // step name -> its report

  // Steps present, in calibration order ("geometry", "noise", "projector", "graycard").
  std::vector<std::string> Steps() const;
};

// A new, empty calibration of the design rig.
CalibrationData NewCalibration(const Rig& design);

// Writes calibration.json and the EXR files into folder (created), atomically per file.
void SaveCalibration(const std::string& folder, const CalibrationData& data);
// Reads a calibration folder. Throws InputError naming the folder and file if it is not one,
// or is damaged.
CalibrationData LoadCalibration(const std::string& folder);
// Throws InputError unless the calibration belongs to this design rig (same canonical YAML,
// preset included), saying which rig it belongs to.
void CheckCalibrationRig(const CalibrationData& data, const Rig& design, const std::string& folder);

// The design rig with the calibrated misalignment (the design itself without a geometry step).
Rig CalibratedRig(const Rig& design, const CalibrationData& data);

// What capture and processing need: direction maps traced for the calibrated geometry (cached
// in cache_dir), the nominal radiometry of the design, then every measured quantity in place
// of its nominal value. `source` names the calibration ("calibration: <folder>").
RigCalibration ApplyCalibration(const Rig& design, const CalibrationData& data,
                                const std::string& source, const std::string& cache_dir,
                                const ProgressCallback& progress = nullptr);

// LoadCalibration + CheckCalibrationRig + ApplyCalibration; an empty folder name gives the
// nominal calibration of the design rig.
RigCalibration LoadRigCalibration(const Rig& design, const std::string& folder,
                                  const std::string& cache_dir,
                                  const ProgressCallback& progress = nullptr);

}  // namespace zbrdf
