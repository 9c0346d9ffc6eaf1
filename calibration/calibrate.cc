#include "calibration/calibrate.h"

#include <filesystem>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "calibration/calibration_data.h"
#include "calibration/float_image.h"
#include "calibration/graycard.h"
#include "calibration/projector.h"
#include "rig/direction_maps.h"
#include "rig/optics.h"

namespace zbrdf {

namespace {

nlohmann::json MapDifferenceJson(const MapDifference& d) {
  return {{"median_deg", d.median_deg}, {"p95_deg", d.p95_deg}, {"max_deg", d.max_deg},
          {"pixels", d.pixels}};
}

nlohmann::json RunStep(const std::string& step, CalibrationRig& rig, const Rig& design,
                       const CalibrateOptions& options, CalibrationData& data) {
  const std::string& folder = options.folder;
  const std::string source = "calibration: " + folder;
  if (step == "geometry") {
    CalibrationData without = data;
    without.misalignment.reset();
    const RigCalibration current = ApplyCalibration(design, without, source, options.cache_dir, rig.progress);
    const GeometryResult result = CalibrateGeometry(rig, design, current, options.geometry);
    data.misalignment = result.misalignment;
    WriteFloatImage(folder + "/correspondences.exr", result.correspondences.ToImage());
    WriteGeometryFigure(folder + "/geometry.png", result, design);
    nlohmann::json report = result.report;
    // How much the calibrated maps differ from the design's.
    const OpticalSystem nominal_optics(design), calibrated_optics(CalibratedRig(design, data));
    const RigMaps nominal = LoadOrBuildRigMaps(nominal_optics, options.cache_dir, rig.progress);
    const RigMaps calibrated = LoadOrBuildRigMaps(calibrated_optics, options.cache_dir, rig.progress);
    report["camera_map_change"] = MapDifferenceJson(CompareDirectionMaps(nominal.camera, calibrated.camera));
    report["projector_map_change"] =
        MapDifferenceJson(CompareDirectionMaps(nominal.projector, calibrated.projector));
    return report;
  }
  if (step == "noise") {
    const RigCalibration current = ApplyCalibration(design, data, source, options.cache_dir, rig.progress);
    const NoiseResult result = CalibrateNoise(rig, current, options.noise);
    data.sensor = result.sensor;
    WritePhotonTransferPlot(folder + "/noise.png", result);
    return result.report;
  }
  if (step == "projector") {
    CalibrationData without = data;  // measured against the nominal projector and camera
    without.projector_response.reset();
    without.projector_flat.reset();
    without.camera_flat.reset();
    const RigCalibration current = ApplyCalibration(design, without, source, options.cache_dir, rig.progress);
    Correspondences correspondences;
    if (std::filesystem::exists(folder + "/correspondences.exr")) {
      correspondences = Correspondences::FromImage(ReadFloatImage(folder + "/correspondences.exr"),
                                                   folder + "/correspondences.exr");
      if (correspondences.camera_width != current.camera_width ||
          correspondences.camera_height != current.camera_height) {
        correspondences = Correspondences();
      }
    }
    const ProjectorCalibrationResult result = CalibrateProjector(rig, current, correspondences);
    data.projector_response = result.response;
    data.projector_flat = result.projector_flat;
    data.camera_flat = result.camera_flat;
    data.camera_flat_source = "white target";
    WriteProjectorFigures(folder, result);
    return result.report;
  }
  if (step == "graycard") {
    CalibrationData without = data;
    without.scale_rgb.reset();
    const RigCalibration current = ApplyCalibration(design, without, source, options.cache_dir, rig.progress);
    const GrayCardResult result = CalibrateGrayCard(
        rig, design, current, data.camera_flat ? &*data.camera_flat : nullptr,
        folder + "/graycard-session",
        options.pattern_cache_dir.empty() ? options.cache_dir : options.pattern_cache_dir);
    data.camera_flat = result.camera_flat;
    data.camera_flat_source = "gray card";
    data.scale_rgb = result.scale_rgb;
    WriteGrayCardFigure(folder + "/graycard.png", result);
    return result.report;
  }
  throw InputError("unknown calibration step '" + step + "'; valid: geometry, noise, projector, graycard, all");
}

}  // namespace

const std::vector<std::string>& CalibrationSteps() {
  static const std::vector<std::string> steps = {"geometry", "noise", "projector", "graycard"};
  return steps;
}

void CalibrateOptions::Validate() const {
  OptionChecker check("CalibrateOptions");
  check.Require(!folder.empty(), "folder", "must name the calibration folder (--out)")
      .Nested("geometry", geometry)
      .Nested("noise", noise)
      .ThrowIfInvalid();
}

nlohmann::json RunCalibration(const std::string& step, CalibrationRig& rig, const Rig& design,
                              const CalibrateOptions& options) {
  std::vector<std::string> steps;
  if (step == "all") {
    steps = CalibrationSteps();
  } else if (std::find(CalibrationSteps().begin(), CalibrationSteps().end(), step) != CalibrationSteps().end()) {
    steps = {step};
  } else {
    throw InputError("unknown calibration step '" + step + "'; valid: geometry, noise, projector, graycard, all");
  }
  options.Validate();
  CalibrationData data = std::filesystem::exists(options.folder + "/calibration.json")
                             ? LoadCalibration(options.folder)
                             : NewCalibration(design);
  CheckCalibrationRig(data, design, options.folder);
  std::filesystem::create_directories(options.folder);
  nlohmann::json reports = nlohmann::json::object();
  for (const std::string& s : steps) {
    nlohmann::json report = RunStep(s, rig, design, options, data);
    // Steps after this one in the order were measured with what this one replaced.
    std::vector<std::string> stale;
    bool after = false;
    for (const std::string& other : CalibrationSteps()) {
      if (after && data.reports.contains(other)) stale.push_back(other);
      after = after || other == s;
    }
    if (!stale.empty() && step != "all") report["stale_steps"] = stale;
    data.reports[s] = report;
    SaveCalibration(options.folder, data);
    reports[s] = report;
  }
  return reports;
}

}  // namespace zbrdf
