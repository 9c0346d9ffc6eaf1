// Zonal coefficients z_k(w_r) on an exitant grid, and their projection onto the zonal basis in
// w_r (tensor-product coefficients).
//
// A lobe's HDR response at camera pixel p, minus the dark pattern's, divided by the pixel's
// response (e-/s per unit sample radiance) and by the pattern's radiance per unit of Z, is
//   z_k^+-(w_r) = integral_Z Z_k^+-(w_i) f_r(w_i, w_r) cos(theta_i) dw_i
// and z_k = z_k^+ - z_k^- (thesis eq. 3.5). Pixels are resampled onto an exitant grid of
// theta x phi cells over the zone (default 1 x 2 deg), solid-angle weighted: each pixel's
// footprint (4 x 4 points interpolated from the camera's direction map) is split among the
// cells it covers. A cell no pixel reaches (cells near the zone's inner edge can be smaller
// than a pixel) is filled by linear interpolation along its theta row and flagged. Bayer
// channels are resampled separately; a mono camera fills all three. Then
//   z_kj = integral_Z z_k(w_r) Z_j(w_r) dw_r
// is estimated from the cell averages by least squares: with A_cj = integral_cell Z_j (Gauss-
// Legendre) and D = diag(cell solid angles), z_k. = (A^T D^-1 A)^-1 A^T z_k(cells). For z_k
// band-limited to the order this is exact; the plain sum over cells z_k(cell) A_cj would be
// off by -<(I - P) z_k, (I - P) Z_j>, P the cell averaging: 1.6% at order 4 on a 1 x 2 deg
// grid, since Z_lm change fastest near the zone's edges. A^T D^-1 A is within 2% of the
// identity, so the correction does not amplify noise.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "acquisition/rig_calibration.h"
#include "basis/zonal_basis.h"
#include "basis/zone.h"

namespace zbrdf {

struct ExitantGrid {
  double theta_min_rad = 0, theta_max_rad = 0;
  double theta_step_rad = 0, phi_step_rad = 0;
  int n_theta = 0, n_phi = 0;

  int cells() const { return n_theta * n_phi; }
  double ThetaLow(int i) const { return theta_min_rad + i * theta_step_rad; }
  double ThetaHigh(int i) const { return std::min(theta_max_rad, ThetaLow(i + 1)); }
  double CellSolidAngle(int i) const;  // any cell of row i
  // Direction at the cell's center: mid cos(theta), mid phi.
  Vec3 CellCenter(int i, int j) const;
  // Cell index (i * n_phi + j) of direction w; -1 outside the zone.
  int CellOf(const Vec3& w) const;
};

// Throws InputError for steps outside (0, 10] deg or a zone narrower than one step.
ExitantGrid MakeExitantGrid(const Zone& zone, double theta_step_deg = 1.0, double phi_step_deg = 2.0);

// Per cell and RGB channel: a value, its variance and the solid angle of pixel footprints that
// fell in the cell (0 for a cell filled by interpolation).
struct GridImage {
  std::array<std::vector<float>, 3> value, variance, weight;
  std::vector<uint8_t> filled;  // any channel filled
};

// Splatting weights from camera pixels to grid cells; built once per (calibration, grid).
class PixelToGrid {
 public:
  PixelToGrid(const RigCalibration& calibration, const ExitantGrid& grid, int subsamples = 4);
  // Resamples per-pixel values (with variances; pixels with valid == 0 are skipped).
  GridImage Resample(const std::vector<float>& value, const std::vector<float>& variance,
                     const std::vector<uint8_t>& valid) const;
  const ExitantGrid& grid() const { return grid_; }

 private:
  struct Splat {
    int cell;
    float weight;  // sr
  };
  ExitantGrid grid_;
  std::vector<int64_t> begin_;  // pixel -> first splat
  std::vector<Splat> splats_;
  std::vector<int8_t> channel_;  // pixel -> 0, 1, 2, or -1 (mono: all)
};

// The measured zonal data of a session.
struct ZonalData {
  double theta_min_rad = 0, theta_max_rad = 0;
  int order = 0;
  ExitantGrid grid;
  // Per basis function k (ShIndex order): z_k on the grid.
  std::vector<GridImage> functions;
  // Tensor-product coefficients per channel: rows k (ZB in w_i), columns j (ZB in w_r).
  std::array<Eigen::MatrixXd, 3> tensor, tensor_variance;
  nlohmann::json attributes;  // rig, session, units: stored in the file header

  Zone zone() const { return Zone(theta_min_rad, theta_max_rad); }
};

// Whether the exitant grid of these steps over the zone can hold the order's functions: as
// MakeExitantGrid, and at least order + 1 rows and 2 order + 1 columns (fewer cell averages than
// a band's functions vary over cannot tell them apart). Throws InputError naming the steps, the
// counts and --grid. Run before anything is captured or written.
void CheckExitantGrid(const Zone& zone, int order, double theta_step_deg, double phi_step_deg);

// Integrals of each Z_j (order `order`) over each grid cell: cells x functions.
Eigen::MatrixXd CellIntegrals(const ExitantGrid& grid, const ZonalBasis& zb);
// Fills data.tensor and data.tensor_variance from data.functions (cells independent). Throws
// InputError if the grid is too coarse to resolve the order.
void ProjectExitant(ZonalData* data);

// zonal.exr: a two-part OpenEXR file. Part "grid" (n_phi x n_theta pixels, rows = theta):
// channels Z<l>_<m>.{R,G,B}, Z<l>_<m>.var.{R,G,B}, weight.{R,G,B}, filled; part "tensor"
// (n x n pixels): channels z.{R,G,B}, var.{R,G,B}. Header attributes zbrdf.* carry the zone,
// order, grid and the JSON attributes. docs/session-folder.md specifies it.
void WriteZonalExr(const std::string& path, const ZonalData& data);
// Throws InputError naming the file and what is wrong.
ZonalData ReadZonalExr(const std::string& path);

}  // namespace zbrdf
