// Gray-card calibration (the thesis's reflectance calibration, done per pixel as well): a
// capture session of an 18% gray card with the 9 zonal functions of order <= 2, with the
// calibration so far. Then
//  - the camera's flat field: a diffuse card looks the same from every camera pixel, so each
//    pixel's DC coefficient z_00(pixel) over its Bayer channel's median is the factor by which
//    the pixel's response was off (applied on top of the flat field so far);
//  - the session re-processed with that flat field; the measured coefficients z_l0 (l <= 2)
//    averaged over the exitant grid (solid-angle weighted);
//  - per-channel scale factors so that the DC term matches an 18% Lambertian reflector,
//    scale_rgb = z_00(ideal) / z_00(measured), ideal z_lm = 0.18/pi integral Z_lm cos(theta) dw;
//  - the deviations of the scaled l = 1 and l = 2 terms from the ideal (largest over the
//    channels): l1_deviation = |s z_10 - z_10(ideal)| / |z_10(ideal)|, and
//    l2_deviation = |s z_20 - z_20(ideal)| / |z_00(ideal)|, relative to the DC term because
//    z_20(ideal) is exactly 0: cos(theta) is linear in the zonal basis's virtual coordinate t,
//    and Z_l0 (a Legendre polynomial in t) is orthogonal to linear functions for l >= 2. So a
//    Lambertian reflector has only the l = 0 and l = 1 terms (m = 0) in any zone.
// The thesis found 2% and 10% after DC matching; a figure like its figure 3.6 shows measured
// and ideal coefficients for l <= 2, m = 0.
#pragma once

#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "basis/zone.h"
#include "calibration/calibration_data.h"
#include "calibration/rig_access.h"

namespace zbrdf {

struct GrayCardResult {
  std::array<double, 3> scale_rgb{1, 1, 1};
  PixelField camera_flat;  // the new total camera flat field
  std::array<double, 3> ideal{};                     // z_l0 of 18% Lambertian, l = 0, 1, 2
  std::array<std::array<double, 3>, 3> measured{};   // [l][channel], scaled
  double l1_deviation = 0, l2_deviation = 0;
  nlohmann::json report;
};

// `calibration` is the calibration so far; `prior_camera_flat` the camera flat field in it
// (null if none). The session is written to session_dir (replaced if it holds an earlier
// gray-card session).
GrayCardResult CalibrateGrayCard(CalibrationRig& rig, const Rig& design,
                                 const RigCalibration& calibration,
                                 const PixelField* prior_camera_flat, const std::string& session_dir,
                                 const std::string& pattern_cache_dir);

// The ideal zonal coefficients of a Lambertian reflector of albedo rho over the zone, for
// Z_l0, l <= max_l (m != 0 vanish): rho/pi integral_zone Z_l0(w) cos(theta) dw.
std::vector<double> LambertianZonalCoefficients(const Zone& zone, int max_l, double rho);

// Measured (scaled) against ideal coefficients for l <= 2, m = 0 (PNG).
void WriteGrayCardFigure(const std::string& path, const GrayCardResult& result);

}  // namespace zbrdf
