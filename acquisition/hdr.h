// High-dynamic-range merge of an exposure bracket of raw frames.
//
// Linear sensor model (docs/design.md section 4): a sample v of a pixel exposed for t seconds gives
// the photo-electron rate estimate x = (v - black) g / t (g in e-/DN), with variance
// (X t + sigma_read^2 + g^2 / 12) / t^2 for the true rate X. Samples at or above the safe
// saturation level (95% of the way from black to saturation) are dropped. Each pixel's rate is
// the inverse-variance weighted mean of its usable samples (Granados et al. 2010), with the
// variance evaluated at the current estimate and iterated; its variance is 1 / sum of weights.
// A pixel with no usable sample (saturated everywhere) is marked invalid, never stored as NaN.
// Frames with NaN-free, in-range values only: a frame of the wrong size, layout or bit depth,
// or with values above its bit depth, is rejected with an InputError naming it.
//
// The merge works on the raw mosaic (one channel per pixel, the Bayer layout's), so each
// sample keeps its own noise; demosaicing (OpenCV) is for the RGB images written for viewing.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "acquisition/rig_calibration.h"
#include "drivers/camera.h"

namespace zbrdf {

struct HdrImage {
  int width = 0, height = 0;
  PixelLayout layout = PixelLayout::kMono;
  std::vector<float> rate;      // photo-electrons per second (camera's own units), per pixel
  std::vector<float> variance;  // of rate
  std::vector<uint8_t> valid;   // 0 where every sample was saturated (rate, variance = 0)
  int saturated_pixels = 0;     // invalid pixels
};

struct HdrOptions {
  double safe_saturation_fraction = 0.95;  // of the range from black to saturation
  int iterations = 3;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

// frames: the same pattern at different exposures (any order). `what` names them in errors.
HdrImage MergeExposures(const std::vector<Frame>& frames, const RigCalibration& calibration,
                        const std::string& what, const HdrOptions& options = {});

// RGB view of an HDR mosaic (demosaiced with OpenCV), CV_32FC3 in R, G, B order, in the same
// units: the mosaic is scaled to 16 bits for OpenCV's demosaicing and scaled back.
cv::Mat HdrToRgb(const HdrImage& hdr);

}  // namespace zbrdf
