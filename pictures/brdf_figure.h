// Side-by-side renderings of BRDFs on spheres (the layout of Ghosh's figure 3.3: ground truth,
// SH reconstruction, D-BRDF fit).
//
// Each panel is an orthographic view of a unit sphere of the material under one directional
// light (40 deg from the view direction, from the upper left), radiance f_r cos(theta_i) = f^ in
// the sample frame at each surface point (tangent along the image's x axis). Values are scaled by
// the first panel's 99.5th percentile, clamped, and sRGB-encoded. Pixels where f^ < 0 in any
// channel (ringing) are painted magenta so that negative values are never hidden; the caption
// under each panel gives its label and the fraction of negative pixels.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "fitting/fit_error.h"

namespace zbrdf {

struct FigurePanel {
  std::string label;
  CosineWeightedFn f_hat;  // f^(w_i, w_o) in the sample frame
};

struct FigureStats {
  std::vector<double> negative_pixel_fraction;  // per panel, of the pixels on the sphere
};

// The panels side by side (size x size pixels each, plus a caption strip), 8-bit BGR. Throws
// InputError if there are no panels or size < 16.
cv::Mat DrawSphereFigure(const std::vector<FigurePanel>& panels, int size = 256,
                         FigureStats* stats = nullptr);

// Writes DrawSphereFigure's image as a PNG. Throws InputError if path does not end in .png or the
// file cannot be written.
FigureStats WriteSphereFigure(const std::string& path, const std::vector<FigurePanel>& panels,
                              int size = 256);

}  // namespace zbrdf
