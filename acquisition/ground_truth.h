// The zonal coefficients a material really has, by direct integration of the material: the
// yardstick for simulated captures (independent of the optics, the sensor and the pipeline).
//
//   z_k(cell) = (1/|cell|) integral_cell integral_Z Z_k(w_i) f_r(w_i, w_r) cos(theta_i) dw_i dw_r
//
// averaged over each exitant cell (a capture measures cell averages) with a 2 x 2
// Gauss-Legendre rule in (cos theta_r, phi_r) within the cell. The inner integral uses a
// Gauss-Legendre (psi) x trapezoid product rule over the zone for materials without a glossy
// part (exact for polynomial BRDFs such as Lambertian), and otherwise multiple importance
// sampling of the zone (cosine-weighted) and of the material's glossy lobe with a scrambled
// (0,2)-net of `samples` points. A delta material (mirror) is evaluated in closed form. For an
// isotropic material (Brdf::IsIsotropic) each grid row is integrated once, at phi_r = 0 (2
// Gauss-Legendre points in cos theta_r, 4 x `samples` each), and each cell's value follows
// exactly by rotating the (cos m phi, sin m phi) pair of every band and averaging over the
// cell's azimuths.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "acquisition/zonal.h"
#include "brdf/brdf.h"

namespace zbrdf {

struct GroundTruthOptions {
  int samples = 4096;  // incident samples per exitant point (glossy materials)
  int phi_stride = 6;  // every theta row, every phi_stride-th column of the grid
  uint64_t seed = 99;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct GroundTruth {
  std::vector<int> cells;  // grid cells evaluated
  // value[k][ch][i]: function k, channel ch, cell cells[i].
  std::vector<std::array<std::vector<double>, 3>> value;
};

GroundTruth TrueZonalCoefficients(const Brdf& material, const ZonalData& layout,
                                  const GroundTruthOptions& options = {});

// TrueZonalCoefficients through a cache folder (docs/simulator.md, "Caches"): one entry per
// material (MaterialCacheKey), zone, exitant grid, order and options, written atomically
// (concurrent processes may share the folder). Empty cache_dir: no cache.
GroundTruth TrueZonalCoefficientsCached(const Brdf& material, const ZonalData& layout,
                                        const GroundTruthOptions& options,
                                        const std::string& cache_dir);

// Relative L2 error of the measured z_k over the ground truth's cells (solid-angle weighted,
// all functions and channels): ||z_measured - z_true|| / ||z_true||.
double CoefficientError(const ZonalData& measured, const GroundTruth& truth);

}  // namespace zbrdf
