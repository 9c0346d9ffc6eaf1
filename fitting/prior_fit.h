// Whole-hemisphere BRDFs from zonal data: a measured-material prior (brdf/brdf_prior.h) fitted in
// coefficient space (docs/design.md section 4; docs/prior.md has the method and its accuracy).
//
// The model, per RGB channel c: f_c = sum_k a_ck atom_k (+ a_c0 / pi, a Lambertian atom), a_ck >=
// 0, where the atoms are the prior's tables (every channel of every material may serve any
// channel: a red material's specular lobe may be another's green one). Its zonal coefficients
// are A a_c with A = the projection of each atom on the session's zone and order (PeakProjector,
// fitting/peak_projection.h: the atoms' specular peaks are sub-degree), computed once per zone,
// order and prior. The weights minimize
//   sum_i ((A a_c - z_c)_i / sigma_ci)^2,   sigma_ci^2 = var_ci + (floor rms(z_c))^2,
// by non-negative least squares (Lawson & Hanson 1974) on the isotropic coefficients (fit_data.h).
// The floor stands for what the variances do not hold: the capture's systematic error (0.5-4%
// of the coefficients on the simulated thesis rig, 40-400x the noise) and the prior's
// tabulation. Non-negativity is the regularization: the fit can only combine measured
// behaviour, so it never extrapolates past the library (no blow-up at grazing angles, where
// the rig does not look), and reciprocity and symmetry hold by construction.
//
// Second stage, extrapolation by the prior's statistics (Nielsen, Jensen & Ramamoorthi 2015): the
// combination fits the zone well but outside it inherits whichever materials explained the zone.
// Its values at the grid nodes whose two directions lie in the zone become dense observations
// y = log(f cos(theta_i) cos(theta_o) + eps) for a principal-component model of the prior's
// atoms in the same log map; the components' weights are the ridge solution with the prior's
// own variances (the posterior mean of a Gaussian on the weights), and the table becomes
// exp(mean + V w) mapped back. On the simulated thesis rig (order 8, fast preset, 98 MERL
// materials left out one at a time) this lowered the median hemisphere error from 0.42 to 0.38
// and at theta <= 80 deg from 0.35 to 0.31, but raised them on materials of another device
// (the RGL set, 0.61 / 0.45 to 0.68 / 0.58): the components carry MERL's own grazing behaviour.
// The result is therefore the mean of the two tables (pca_weight), which keeps most of the gain
// on MERL (0.37 / 0.31) and the robustness elsewhere (RGL 0.58 / 0.51); docs/prior.md has the
// numbers. pca_components = 0 skips the second stage.
//
// Uncertainty: `replicates` refits, each on a random half of the atoms (fixed seed) and the data
// perturbed by their sigma; the per-node standard deviation of those tables is the reported
// one-sigma uncertainty: it is small where the data pin the table and large where materials that
// agree in the zone disagree outside it.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "brdf/brdf_prior.h"
#include "brdf/tabulated_brdf.h"
#include "fitting/fit_common.h"
#include "fitting/fit_data.h"
#include "fitting/peak_projection.h"

namespace zbrdf {

struct PriorFitOptions {
  double model_error_floor = 0.01;   // relative to each channel's RMS coefficient
  bool lambertian_atom = true;
  int replicates = 8;                // refits for the uncertainty; 0: none
  double replicate_atom_fraction = 0.5;
  uint64_t seed = 1;
  // Prior materials left out of the fit (leave-one-out benchmarks); unknown names are ignored.
  std::vector<std::string> exclude;
  int pca_components = 20;           // second stage; 0: the combination is the result
  double pca_ridge = 1.0;            // weight of the components' prior variances
  double pca_epsilon = 1e-3;         // offset of the log map, in 1/sr (f cos cos units)
  // The result is pca_weight x the second stage + (1 - pca_weight) x the combination: an equal
  // ensemble of two estimators with different biases (docs/prior.md: the second stage alone is
  // better on MERL and worse on the RGL validation set; 0.5 was set before looking at RGL).
  double pca_weight = 0.5;
  PeakProjectionOptions projection;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct PriorFitResult {
  std::shared_ptr<const TabulatedBrdf> brdf;  // values and one-sigma uncertainty
  bool fitted = false;                        // false for degenerate data (see conditions)
  FitStatistics statistics;                   // on the isotropic coefficients, floor included
  std::array<Eigen::VectorXd, 3> model;       // the fit's isotropic coefficients (fit_data.h)
  struct Contribution {
    std::string material;  // "lambertian" for the Lambertian atom
    int channel = 0;       // the atom's channel in its material
    double share = 0;      // of the channel's coefficient energy it explains (a_k ||A_k||)
  };
  std::array<std::vector<Contribution>, 3> contributions;  // per output channel, largest first
  int atoms_available = 0, atoms_used = 0;
  int pca_components = 0;                     // of the second stage (0: not applied)
  std::vector<std::string> excluded;          // materials actually left out
  // RMS one-sigma uncertainty over RMS value, cosine-weighted over the hemisphere and over the
  // zone: how far the data pin the table (docs/prior.md).
  double relative_uncertainty_hemisphere = 0, relative_uncertainty_zone = 0;
  std::vector<std::string> conditions;
  double precompute_seconds = 0, solve_seconds = 0, total_seconds = 0;

  nlohmann::json ToJson() const;
};

// Non-negative least squares min ||A x - b|| s.t. x >= 0 from the normal equations M = A^T A,
// v = A^T b (Lawson & Hanson 1974, ch. 23, in Gram form): fast for a few hundred columns. The
// passive set is solved by LDLT with a relative ridge of 1e-12 trace(M) / n.
Eigen::VectorXd NonNegativeLeastSquaresGram(const Eigen::MatrixXd& m, const Eigen::VectorXd& v);

class PriorFitter {
 public:
  // Projects the prior's grid on the zone and order (about 1-2 s at order 8), unless
  // `table_projection` (TableProjection() of an equal fitter, e.g. from a cache) is given.
  // Throws InputError for bad options or a table_projection of the wrong size.
  PriorFitter(const Zone& zone, int order, std::shared_ptr<const BrdfPrior> prior,
              const PriorFitOptions& options = {},
              const Eigen::MatrixXf* table_projection = nullptr);

  // Throws InputError if the data's zone or order differ from the fitter's or the data are
  // malformed. Degenerate data do not throw: the result says so.
  PriorFitResult Fit(const ZonalTensor& data) const;
  // The same with other options (exclusions, replicates), reusing the projection.
  PriorFitResult Fit(const ZonalTensor& data, const PriorFitOptions& options) const;

  // Isotropic coefficients x columns: the prior's atoms (3 per material), then the Lambertian.
  const Eigen::MatrixXd& AtomProjection() const { return projection_; }
  // Isotropic coefficients x grid nodes: the projection of a table (PeakProjector).
  const Eigen::MatrixXf& TableProjection() const { return table_projection_; }
  const BrdfPrior& prior() const { return *prior_; }
  double precompute_seconds() const { return precompute_seconds_; }

 private:
  Zone zone_;
  int order_;
  std::shared_ptr<const BrdfPrior> prior_;
  PriorFitOptions options_;
  struct LogPca {
    std::vector<std::string> excluded;  // the materials it was built without
    int components = 0;
    double epsilon = 0;
    Eigen::VectorXd mean, sigma;        // sigma: standard deviation of each component's weight
    Eigen::MatrixXd basis;              // grid nodes x components
  };
  // The principal components of the atoms (without `excluded`), cached for the last set.
  std::shared_ptr<const LogPca> Pca(const std::vector<std::string>& excluded,
                                    const PriorFitOptions& options) const;
  // The second stage on one channel's table (in place): pca_weight x its extrapolation +
  // (1 - pca_weight) x the table.
  void Extrapolate(const LogPca& pca, double ridge, double weight,
                   std::vector<double>* table) const;

  Eigen::MatrixXf table_projection_;
  Eigen::MatrixXd projection_;
  std::vector<double> log_weight_;  // max(cos(theta_i) cos(theta_o), 1e-3) per node
  std::vector<int> zone_nodes_;     // nodes with both directions in the zone
  mutable std::mutex pca_mutex_;
  mutable std::shared_ptr<const LogPca> pca_;
  double precompute_seconds_ = 0;
};

}  // namespace zbrdf
