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
// 4. Refinement of c (RGB), F0, kd (RGB) and p, minimizing the inverse-variance weighted
//    difference between the model's zonal projection and the measured coefficients (the isotropic
//    blocks for a 1-D table, the full tensor for a 2-D one), with p >= 0, F0 in [f0_min, f0_max],
//    c, kd >= 0; the c-p scale is a gauge, fixed by normalizing p (integral p cos dw = 1).
//    p's free values are knots at table nodes spaced max(2, min(6, theta / 4)) deg up to
//    theta_max (the largest theta_h two zone directions have); between knots p is the GGX lobe
//    of step 2 times a linearly interpolated ratio, beyond the last one the GGX tail scaled to
//    continue it: the data do not constrain p there. The solver alternates exact minimizations,
//    each a non-negative quadratic: (p, kd) for fixed F0 and c (Lawson-Hanson active set on the
//    normal equations), then (F0, c, kd) for fixed p (per channel in closed form, F0 by a 1-D
//    search); then Ceres polishes all parameters together (kept only if better). The model is
//    linear in p and kd for fixed (F0, c), so each step solves its sub-problem exactly (F0 to
//    the search's tolerance) and the objective does not rise.
//    The projections come from a half-vector quadrature with at least two psi nodes per degree
//    of the zone's width (below).
// 5. If step 4 leaves a misfit beyond the data's noise (chi2 more than 3 standard deviations
//    above dof: the capture's systematic errors, or a material the D-BRDF cannot represent),
//    step 4 is repeated with a smoothness prior: residuals on the second differences of the ratio
//    p / GGX between knots (in theta / theta_max), weighted by smoothness * sqrt(excess chi2 /
//    rows). Second differences leave the GGX shape and any linear trend of the ratio free; exact
//    or noise-level data skip this step. The prior is kept only if it raises the data's chi2 by
//    at most 10% (else its weight is lowered 10x, twice, then it is dropped): a misfit that is
//    the model's own (a mirror at low order) is not the capture's error, and the data must
//    outweigh the prior there.
// Uncertainties come from ceres::Covariance at the solution (with step 5's prior when it was
// applied), scaled by max(1, chi2/dof).
//
// Why the fit used to miss its data (merl:blue-acrylic, the demo: order 4, full preset, zone
// 9.7-56.5 deg: chi2/dof 6.6e5, relative residual 13.5%, error in the zone 0.84, peak at normal
// incidence 0.88 1/sr), measured by fitting both the session and the material's exact projection
// (a converged 192-node rule), docs/fitting.md has the tables:
//   - Most of the misfit is the model's. The D-BRDF fitted to the exact projection leaves 12.2%
//     (order 4) and 16.4% (order 8, fast zone); gold-metallic-paint 16.2%, alum-bronze 27%,
//     chrome 23%, pink-felt 2.2%. Its angular factor 1 / (k1.n + k2.n - (k1.n)(k2.n)) grows
//     2.4x less across the zone than a microfacet lobe's G / (4 cos cos), and p(h), a function of
//     theta_h alone, cannot make that up; only Schlick's rise with a small F0 can, which the
//     default F0 floor (0.04) forbids. A GGX material (alpha 0.05, F0 0.04, kd 0.1) is fitted to
//     17% with kd driven to 0; with f0_min = 0 to 8% with kd right.
//   - The capture's own error: the session's coefficients differ from the exact projection by
//     4.9% (order 4) and 8.6% (order 8), so even the true material has chi2/dof 4.7e4 and 2.6e4
//     against them (the sub-degree specular peak). No model reaches the noise there.
//   - The solver: Levenberg-Marquardt with bounds on 15 knots stopped early ("parameter
//     tolerance reached") whenever p met its bound. The alternating solver reaches a lower chi2
//     on every session (without the prior, same quadrature: blue-acrylic 16.0 -> 15.5%, gold
//     17.1 -> 15.9%, alum-bronze 27.7 -> 26.0%, chrome 22.9 -> 22.0%), fits a D-BRDF with
//     p = (D_0.02 + D_0.2) / 2 to 2.1e-4 instead of 1.4e-3 (c and kd within 0.2% instead of
//     9.5% and 7% off), and takes the demo to 12.4%, error in the zone 0.77 and a peak of
//     2.1 1/sr (the 1 deg table cannot hold the material's sub-degree peak).
//   - The quadrature: the default psi rule (40 nodes at order 4 on this zone, 48 at order 8)
//     integrates a table node's projection to 13% and 2.6% (theta_h = 0) and 0.2-1.5% (the
//     others), and the fit traded its parameters for that error (a 3 deg lobe at order 4: kd 8%
//     and c F0 4% off). At two nodes per degree, 0.5% and 0.01-0.09%: kd 0.05%, c F0 0.09%.
//     (The MERL fits barely change: their fitted lobes span several table steps.)
//   - Not causes: p >= 0 and its normalization (exact: the gauge is fixed after each sweep), the
//     GGX scan's alpha range (the retro or GGX start only seeds step 4), the knot layout (p free
//     at every 1 deg node fits no material better: blue-acrylic 15.6% vs 15.5%; on the exact
//     projection of a D-BRDF it reaches 1.5e-5, but on physical data it fits the quadrature's
//     error instead, with in-zone errors of 27% for a 2 deg lobe).
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
  int max_sweeps = 400;      // alternating solver (step 4)
  int max_iterations = 100;  // Ceres polish after it
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
