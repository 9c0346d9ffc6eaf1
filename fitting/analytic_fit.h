// Fitting analytic BRDF models (GGX, Ward, Ashikhmin-Shirley; isotropic) to measured zonal
// coefficients, the same way as the D-BRDF (dbrdf_fit.h): in coefficient space, weighted by the
// coefficients' variances, by Ceres (Ghosh 2007, section 3.2.3: "the measured zonal data can be
// fitted to any other suitable analytic model using ... Levenberg-Marquardt").
//
// Each model is, for a fixed lobe-shape parameter x, linear in its colours:
//   model_ch = O(x) + a_ch S(x) + b_ch D
//   ggx   x = alpha;   a = F0 (Schlick's F = F0 (1 - W) + W, W = (1 - w_o.h)^5), b = kd;
//         O = the lobe with F = W, S = the lobe with F = 1 - W
//   ward  x = alpha;   a = rho_s, b = rho_d; O = 0
//   as    x = n (nu = nv); a = Rs, b = Rd (1 - Rs) (the diffuse term's factor); O, S as for GGX
// with D the diffuse term's projection. The projections O, S, D are computed by the half-vector
// quadrature (fit_quadrature.h) from the models' own Eval. The fit scans x (log scale) with the
// colours solved by non-negative least squares (variable projection), then Ceres refines all
// seven parameters jointly: x by central differences, the colours analytically, with bounds
// a in [0, 1] (ggx, as) or >= 0 (ward), b >= 0. Anisotropic data are fitted with the isotropic
// model on their azimuthal average; the result says so.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "brdf/brdf.h"
#include "fitting/fit_common.h"
#include "fitting/fit_data.h"
#include "fitting/fit_quadrature.h"

namespace zbrdf {

enum class AnalyticModel { kGgx, kWard, kAshikhminShirley };
// "ggx", "ward", "as".
std::string AnalyticModelName(AnalyticModel model);
// Throws InputError listing the accepted names.
AnalyticModel ParseAnalyticModel(const std::string& name);

struct AnalyticFitOptions {
  int max_iterations = 30;
  bool covariance = true;
  // Lower bound of Schlick's F0 (ggx: F0, as: Rs) in every channel; not applied to Ward's rho_s,
  // which has no Fresnel term. Schlick's F rises to 1 at grazing angles whatever F0 is, so a
  // sharp lobe fitted with a tiny F0 grows by ~1/F0 outside the zone (merl:specular-orange-
  // phenolic on the thesis zone: F0 0.006, f_r 60x the truth's at 85 deg, error_cosine_l2 44).
  // A floor of 0.02 (water, the least a real surface reflects) tames that (44 -> 3.6) but costs
  // in the zone (0.40 -> 0.85): the bundled materials' lobes carry only 0.4-1% of the light
  // there, so the in-zone data ask for the small F0. Hence off by default (issue 6).
  double f0_min = 0.0;
  // A coarser half-vector quadrature than the D-BRDF's suffices for these smooth lobes
  // (3 deg cells; fit_quadrature_test.cc checks the projection against a brute-force rule).
  PairQuadratureOptions quadrature{0, 30, 4};

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct AnalyticFitResult {
  AnalyticModel model = AnalyticModel::kGgx;
  bool fitted = false;
  std::shared_ptr<const Brdf> brdf;  // always set; a black Lambertian for degenerate data
  std::string spec;                  // brdf->Spec()
  double shape = 0;                  // alpha (ggx, ward) or n (as)
  Rgb specular;                      // F0 / rho_s / Rs
  Rgb diffuse;                       // kd / rho_d / Rd
  struct Uncertainty {
    bool available = false;
    double shape = std::numeric_limits<double>::quiet_NaN();
    Rgb specular{std::numeric_limits<double>::quiet_NaN()};
    Rgb diffuse{std::numeric_limits<double>::quiet_NaN()};
  } uncertainty;
  IsotropyReport isotropy;
  FitStatistics statistics;
  std::vector<std::string> conditions;
  double precompute_seconds = 0, solve_seconds = 0, total_seconds = 0;

  // "params": {alpha | n, F0 | rho_s | Rs, kd | rho_d | Rd} with the spec's key names.
  nlohmann::json ToJson() const;
};

class AnalyticFitter {
 public:
  AnalyticFitter(const Zone& zone, int order, const AnalyticFitOptions& options = {});
  // Throws InputError if the data's zone or order differ from the fitter's. Degenerate data do
  // not throw (see AnalyticFitResult::conditions).
  AnalyticFitResult Fit(const ZonalTensor& data, AnalyticModel model) const;

  const PairQuadrature& quadrature() const { return quadrature_; }

 private:
  Zone zone_;
  int order_;
  AnalyticFitOptions options_;
  PairQuadrature quadrature_;
  double precompute_seconds_ = 0;
};

}  // namespace zbrdf
