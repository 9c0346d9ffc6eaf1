// Fitting the D-BRDF (dbrdf.h) to measured zonal coefficients (Ghosh 2007, section 3.2.3;
// docs/design.md section 4: fit in coefficient space, never to a ringing SH reconstruction).
//
// 1. Isotropy (fit_data.h) decides the table: 1-D p(theta_h) (91 nodes, 1 deg) for isotropic
//    data, 2-D p(theta_h, phi_h) (46 x 8 nodes) for anisotropic data.
// 2. Initial lobe: a GGX-shaped p = D_alpha (normalized) scanned over alpha, with c F0, c and kd
//    per channel by non-negative least squares on the whole tensor (variable projection; cheap
//    because the model is linear in p, see fit_quadrature.h).
// 3. Retro-reflection extraction (thesis eq. 2.15): the band-limited retro slice
//    f^(w, w) = sum_kj z_kj Z_k(w) Z_j(w) gives, inside the zone,
//      c F0 p(theta_h = theta) = (f^(w, w) / cos(theta) - kd / pi) (2 cos(theta) - cos^2(theta)),
//    combined over channels by least squares and clamped at 0. Outside the zone (theta below
//    theta_min, where the specular peak lies, and above theta_max) the GGX lobe of step 2 is the
//    tail; the two are blended linearly over 5 deg at each zone edge.
// 4. Ceres refinement of c (RGB), F0, kd (RGB) and p, minimizing the inverse-variance weighted
//    difference between the model's zonal projection and the measured coefficients (the isotropic
//    blocks for a 1-D table, the full tensor for a 2-D one), with p >= 0, F0 in [0, 1], c, kd >= 0
//    and the normalization integral p cos dw = 1 held by a residual (the c-p scale is a gauge).
//    p's free values are knots at table nodes spaced max(2, min(6, theta / 4)) deg up to
//    theta_max (the largest theta_h two zone directions have); between knots p is the GGX lobe
//    of step 2 times a linearly interpolated ratio, beyond the last one the GGX tail scaled to
//    continue it: the data do not constrain p there.
// 5. If step 4 leaves a misfit beyond the data's noise (chi2 > dof: the capture's systematic
//    errors, or a material the D-BRDF cannot represent), step 4 is repeated with a smoothness
//    prior: residuals on the second differences of the ratio p / GGX between knots (in theta /
//    theta_max), weighted by smoothness * sqrt(excess chi2 / rows). Second differences leave the
//    GGX shape and any linear trend of the ratio free; exact or noise-level data skip this step.
//    The prior is kept only if it raises the data's chi2 by at most 10% (else its weight is
//    lowered 10x, twice, then it is dropped): a misfit that is the model's own (a mirror at low
//    order) is not the capture's error, and the data must outweigh the prior there.
// Uncertainties come from ceres::Covariance at the solution (with step 5's prior when it was
// applied), scaled by max(1, chi2/dof).
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "brdf/dbrdf.h"
#include "fitting/fit_common.h"
#include "fitting/fit_data.h"
#include "fitting/fit_quadrature.h"

namespace zbrdf {

struct DBrdfFitOptions {
  enum class Table { kAuto, kIsotropic, kAnisotropic };
  Table table = Table::kAuto;
  int theta_samples = 91;                 // 1-D table
  int anisotropic_theta_samples = 46;     // 2-D table
  int anisotropic_phi_samples = 8;
  int max_iterations = 100;
  bool covariance = true;
  // Bounds of Schlick's F0. The zone sees the Fresnel rise only weakly (at most (1 - cos 57)^5 =
  // 2% of 1 - F0 on the thesis zone), so a small F0 with a large c can imitate other angular
  // trends of the data and explode at grazing angles outside the zone. 0.02 (water, the least
  // reflective common dielectric) is the physical floor. f0_min == f0_max fixes F0.
  double f0_min = 0.04, f0_max = 1.0;
  // Weight of the smoothness prior on p (step 5 above). With 15 knots, p's tail near theta_max
  // (few zone pairs reach such half vectors) and kd are nearly degenerate, so a capture's
  // systematic coefficient errors, which exceed its noise, move kd and c a lot: on the simulated
  // thesis rig (fast preset, order 8) a 0.3% coefficient error put kd 8-15% high and c F0 7%
  // low, with p's tail collapsing to 0. The prior penalizes the curvature of p / s (s: the GGX
  // lobe of step 2) with a weight such that a unit curvature costs `smoothness` squared times the
  // misfit the unregularized fit leaves beyond the noise: data the model explains (exact or
  // within their noise) are fitted without it, and so without bias. 1 brings that session to
  // kd 0.1%, c F0 0.2%, p 0.2%; 3-100 give the same within 1%. 0 turns the prior off.
  double smoothness = 1.0;
  PairQuadratureOptions quadrature;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct DBrdfFitResult {
  DBrdfParams params;            // a valid, normalized D-BRDF (black if nothing was fitted)
  bool fitted = false;           // false when the data are degenerate (see conditions)
  bool isotropic_table = true;
  IsotropyReport isotropy;
  double tail_alpha = 0;         // GGX alpha of the initial lobe and of the tail
  // The GGX alpha whose retro-reflection slice has the fitted model's shape (up to theta_max):
  // p compared with D G2 (2 - cos) / (4 cos), the p a GGX lobe has at retro-reflection.
  double alpha_equivalent = 0;
  int knots = 0;                 // free p values
  double smoothness_weight = 0;  // the prior's residual weight in step 5 (0: not applied)
  std::string initial;           // "retro+ggx" or "ggx": the starting point Ceres refined
  FitStatistics statistics;
  struct Uncertainty {
    bool available = false;
    double f0 = std::numeric_limits<double>::quiet_NaN();
    Rgb c{std::numeric_limits<double>::quiet_NaN()}, kd{std::numeric_limits<double>::quiet_NaN()};
  } uncertainty;                 // one standard deviation
  std::vector<std::string> conditions;
  double precompute_seconds = 0, solve_seconds = 0, total_seconds = 0;

  nlohmann::json ToJson() const;
};

// Precomputes the projections for a zone and order once (the quadrature, ~0.1 s; the 1-D table's
// projection; the 2-D one on first use), then fits any number of data sets on that zone.
class DBrdfFitter {
 public:
  DBrdfFitter(const Zone& zone, int order, const DBrdfFitOptions& options = {});
  ~DBrdfFitter();

  // Throws InputError if the data's zone or order differ from the fitter's or the data are
  // malformed (sizes). Degenerate data (zero, noise only, non-finite entries) do not throw:
  // the result says so in `conditions` and `fitted`.
  DBrdfFitResult Fit(const ZonalTensor& data) const;

  const PairQuadrature& quadrature() const { return *quadrature_; }
  double precompute_seconds() const { return precompute_seconds_; }

 private:
  const DBrdfProjection& Projection(bool isotropic) const;

  Zone zone_;
  int order_;
  DBrdfFitOptions options_;
  std::unique_ptr<PairQuadrature> quadrature_;
  mutable std::unique_ptr<DBrdfProjection> isotropic_, anisotropic_;
  mutable double precompute_seconds_ = 0;
};

// One-shot convenience: DBrdfFitter(data.zone(), data.order, options).Fit(data).
DBrdfFitResult FitDBrdf(const ZonalTensor& data, const DBrdfFitOptions& options = {});

}  // namespace zbrdf
