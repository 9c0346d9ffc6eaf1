// Projector calibration: the response curve and the flat field that pattern generation uses
// (acquisition/patterns.h inverts the one and divides by the other).
//
// Response: uniform patterns at 33 levels (every 8th, and the top) on the white target, each an
// HDR image (3 exposures 2 stops apart from the full-white metering); the response at a level is
// the mean over the lit camera pixels of its image minus the level-0 image, over the same for
// the top level. The measured points are made non-decreasing and interpolated to every level
// with a monotone cubic (Fritsch-Carlson). The level-0 image over the full range is the black
// fraction (ambient light included).
//
// Camera flat field (white target): under a uniform pattern every camera pixel sees the same
// radiance of a diffuse target, so each pixel's full-white image over its nominal response is
// its flat-field factor (normalized to a median of 1 per Bayer channel).
//
// Projector flat field: the thesis photographed a mid-gray full-screen pattern on a screen
// outside the rig. A diffuse target in the sample position cannot show it (every camera pixel
// integrates all projector pixels), so zbrdf uses the mirror target: through the mirror each
// camera pixel sees one projector pixel (the Gray-code correspondences of the geometry step),
// so the HDR image of a mid-gray pattern, over the camera pixel's response, is the projector
// pixel's output along the path it lights the sample by: lens falloff, mirror and beam-splitter
// variation and vignetting at the rims included. Projector pixels seen by several camera
// pixels average them; a normalized Gaussian convolution (sigma 1.5 pixels) smooths and fills
// the ones no camera pixel saw; the field is scaled to 1 at its 99.5th percentile.
#pragma once

#include <nlohmann/json.hpp>

#include "calibration/calibration_data.h"
#include "calibration/gray_code.h"
#include "calibration/rig_access.h"

namespace zbrdf {

struct ProjectorCalibrationResult {
  ProjectorResponseCalibration response;
  PixelField projector_flat;
  PixelField camera_flat;           // from the white target
  std::vector<uint8_t> projector_seen;  // projector pixels some camera pixel saw (the rest filled)
  std::vector<int> levels;          // measured
  std::vector<double> measured;     // normalized response at those levels
  nlohmann::json report;
};

// `calibration` is the calibration so far (geometry and noise applied); `correspondences` from
// the geometry step (if empty, they are captured here with the mirror in place).
ProjectorCalibrationResult CalibrateProjector(CalibrationRig& rig, const RigCalibration& calibration,
                                              Correspondences correspondences);

// Monotone cubic interpolation (Fritsch-Carlson) of non-decreasing points (x ascending) at
// every integer from x.front() to x.back().
std::vector<double> MonotoneInterpolate(const std::vector<int>& x, const std::vector<double>& y);

// Response curve (measured points and the interpolated table) and flat-field picture (PNGs).
void WriteProjectorFigures(const std::string& folder, const ProjectorCalibrationResult& result);

}  // namespace zbrdf
