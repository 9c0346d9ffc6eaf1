// Runs calibration steps on a rig and keeps their results in a calibration folder
// (calibration_data.h): `zbrdf calibrate` and the tests call this.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "calibration/geometry.h"
#include "calibration/noise.h"
#include "calibration/rig_access.h"

namespace zbrdf {

struct CalibrateOptions {
  std::string folder;             // the calibration folder (created, or updated)
  std::string cache_dir;          // direction maps
  std::string pattern_cache_dir;  // gray-card session patterns ("" : cache_dir)
  GeometryOptions geometry;
  NoiseOptions noise;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

// The steps in calibration order.
const std::vector<std::string>& CalibrationSteps();

// Runs `step` ("geometry", "noise", "projector", "graycard", or "all" for the four in order),
// each with what the folder holds from the earlier steps, and saves the folder after each.
// Returns the reports of the steps run (step -> report). Throws InputError for an unknown step
// or a folder of another rig, DeviceError when the rig fails (what was saved stays).
nlohmann::json RunCalibration(const std::string& step, CalibrationRig& rig, const Rig& design,
                              const CalibrateOptions& options);

}  // namespace zbrdf
