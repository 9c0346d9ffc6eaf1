// A BRDF sampled into a MERL .binary table (Matusik et al. 2003; format in brdf/merl_table.h
// and docs/formats.md), readable by MERL's reference reader (BRDFRead.cpp) and by Disney's BRDF
// Explorer.
//
// Each bin (theta_h index i, theta_d index j, phi_d index k) holds f_r at its center:
//   theta_h = ((i + 1/2) / 90)^2 pi/2   (the center of the bin on the square-root axis)
//   theta_d = (j + 1/2) / 90 * pi/2,    phi_d = (k + 1/2) / 180 * pi
// with h at azimuth 0, w_i = R_z(phi_h) R_y(theta_h) d(theta_d, phi_d) and w_o its mirror image
// about h (Rusinkiewicz 1998). Bins whose center pair is below the horizon hold 0, as f_r does
// there. The table assumes isotropy (phi_h = 0 stands for every azimuth) and reciprocity
// (the reader folds phi_d into [0, pi)); other inputs are sampled on that half-domain.
#pragma once

#include "brdf/brdf.h"
#include "brdf/merl_table.h"
#include "brdf/value_check.h"

namespace zbrdf {

// The pair of unit directions (w_i, w_o) at a point of the half/difference parameterization
// with phi_h = 0.
void MerlPairAt(double theta_h, double theta_d, double phi_d, Vec3* w_i, Vec3* w_o);
// The center angles of a bin.
void MerlBinCenter(int theta_half_bin, int theta_diff_bin, int phi_diff_bin, double* theta_h,
                   double* theta_d, double* phi_d);

// Samples the BRDF at every bin center (in parallel). *check counts NaN and negative values and
// replaces them with 0 (the caller decides, with check->Finish, whether to fail).
MerlTable SampleMerlTable(const Brdf& brdf, ValueCheck* check);

}  // namespace zbrdf
