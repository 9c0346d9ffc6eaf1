// Projector-camera correspondences through the mirror target, by Gray-code structured light:
// one pattern (and its inverse) per bit of the projector column and row (reflected binary code,
// so that a camera pixel straddling two columns decodes to one of them, never far off), plus
// full white and black for the contrast threshold. With a flat mirror as the sample each lit
// camera pixel sees (about) one projector pixel.
#pragma once

#include <string>
#include <vector>

#include "calibration/float_image.h"
#include "calibration/rig_access.h"

namespace zbrdf {

struct Correspondences {
  int camera_width = 0, camera_height = 0;
  // Per camera pixel: continuous projector pixel coordinates of the centre of the decoded
  // projector pixel (column + 0.5, row + 0.5); -1 where the pixel saw too little contrast.
  std::vector<float> u, v;
  // Full white minus black through the mirror, in DN at the gray code's exposure: the annulus
  // of camera pixels that see projector light, whose edges the geometry fit uses.
  std::vector<float> contrast;
  int count = 0;  // decoded camera pixels

  bool Has(int pixel) const { return u[pixel] >= 0; }
  FloatImage ToImage() const;
  // Throws InputError naming what is wrong.
  static Correspondences FromImage(const FloatImage& image, const std::string& what);
};

// Bits needed for n columns (or rows).
int GrayCodeBits(int n);
// Level pattern of one bit of the Gray code of the columns (rows if `rows`), inverted or not.
Pattern GrayCodePattern(const RigCalibration& calibration, int bit, bool rows, bool inverted);

// Shows the patterns at one exposure (metered on full white: the mirror target must be in
// place) and decodes them. Throws DeviceError if (almost) nothing is decoded.
Correspondences CaptureGrayCode(CalibrationRig& rig, const RigCalibration& calibration);

}  // namespace zbrdf
