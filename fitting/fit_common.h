// Pieces shared by the D-BRDF and analytic fits: residual weights with the data's conditions,
// fit statistics, and small 1-D helpers.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace zbrdf {

// Relative standard deviation added in quadrature to every coefficient's noise: the model
// projection's quadrature error (~2e-5 of the tensor norm, fit_quadrature_test.cc) and float
// storage (6e-8). Keeps noise-free data from giving infinite weights.
inline constexpr double kModelErrorFloor = 3e-5;

// Whitening of measured coefficients for least squares: residual_i = (model_i - y_i) * weight_i.
struct FitWeights {
  std::array<Eigen::VectorXd, 3> y, weight;  // weight 0 marks an unusable entry
  int used = 0;                              // entries with weight > 0, all channels
  bool any_signal = false;                   // some channel's energy exceeds its noise
  double signal_to_noise = 0;                // sqrt(sum y^2 / sum variance), all channels
  // Human-readable notes on degenerate data (non-finite entries dropped, zero variances, ...).
  std::vector<std::string> conditions;
};
// y and variance per channel (same sizes). Non-finite values or variances are excluded.
FitWeights MakeFitWeights(const std::array<Eigen::VectorXd, 3>& y,
                          const std::array<Eigen::VectorXd, 3>& variance);

struct FitStatistics {
  double chi2 = 0;              // sum of squared weighted residuals (data part)
  int residuals = 0, parameters = 0;
  double chi2_per_dof = 0;      // chi2 / max(1, residuals - parameters)
  double relative_residual = 0; // ||model - y|| / ||y|| over used entries, unweighted
  int iterations = 0;
  std::string termination;      // Ceres's message
};
// Statistics of a model prediction against the weights' data.
FitStatistics ComputeFitStatistics(const FitWeights& w, const std::array<Eigen::VectorXd, 3>& model,
                                   int parameters);

// The isotropic GGX distribution D(theta_h) in 1/sr (normalized: integral D cos dw = 1).
double GgxD(double alpha, double theta_h_rad);

// Minimum of f on [lo, hi] by golden-section search after a coarse scan of `scan` points (f may
// have several local minima at the scale of the scan). Returns the argument.
double MinimizeScalar(const std::function<double(double)>& f, double lo, double hi, int scan = 24,
                      int iterations = 40);

// Non-negative least squares min ||A x - b|| s.t. x >= 0 for a few columns (active-set method of
// Lawson & Hanson 1974, ch. 23). Columns that are all zero get x = 0.
Eigen::VectorXd NonNegativeLeastSquares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b);

}  // namespace zbrdf
