// Camera noise calibration, EMVA 1288 style (photon transfer): gain, read noise, dark level
// and saturation from pairs of frames of the white target under a full-white pattern at a
// series of exposures, and a pair of dark frames (projector black).
//
// Per pair A, B: mean mu = mean((A + B) / 2) - mu_dark and temporal variance
// s2 = var(A - B) / 2 - s2_dark over the lit pixels below 70% of saturation (the difference
// removes fixed-pattern and illumination non-uniformity; A + B and A - B are independent, so
// selecting pixels by their mean does not bias the variance). Photon transfer: s2 = mu / g
// (g in e-/DN), fitted through the origin by least squares over the pairs. Dark: mu_dark is
// the black level, s2_dark = (sigma_read / g)^2 + 1/12 (quantization) gives the read noise.
// Saturation: the median of the pixels clipped in an overexposed frame, less 3 dark sigmas.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "calibration/calibration_data.h"
#include "calibration/rig_access.h"

namespace zbrdf {

struct NoiseOptions {
  int exposure_steps = 9;  // pairs from 1/64 of the metered exposure up by factors of 2

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct PhotonTransferPoint {
  double exposure_us = 0;
  double mean_dn = 0;      // above black
  double variance_dn2 = 0; // temporal, dark variance removed
  bool used = false;       // in the linear range, used by the fit
};

struct NoiseResult {
  SensorCalibration sensor;
  std::vector<PhotonTransferPoint> points;
  nlohmann::json report;   // also: the nominal values, fit residual
};

// `calibration` gives the lit pixels and the projector's size (nominal is fine).
NoiseResult CalibrateNoise(CalibrationRig& rig, const RigCalibration& calibration,
                           const NoiseOptions& options = {});

// The photon-transfer plot (variance against mean, with the fit) as a PNG.
void WritePhotonTransferPlot(const std::string& path, const NoiseResult& result);

}  // namespace zbrdf
