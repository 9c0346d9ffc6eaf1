// Pictures of the rig's optics: the dome cross-section with sample ray paths.
#pragma once

#include <string>

#include "rig/optics.h"

namespace zbrdf {

// Writes a PNG of the meridional cross-section (x-z plane) of the rig: sample, parabola, dome
// profile (both sides), camera, and chief rays from camera pixels along the image's middle row
// to the sample, colored from blue (near the normal) to red (grazing). Throws InputError if the
// file cannot be written.
void DrawDomeCrossSection(const OpticalSystem& optics, const std::string& png_path);

// Writes the dome profile as CSV: r_mm, z_mm, normal_r, normal_z, theta_deg, camera_angle_deg.
void WriteDomeProfileCsv(const DomeDesign& design, const std::string& csv_path);

}  // namespace zbrdf
