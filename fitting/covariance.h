// Parameter uncertainties of a Ceres fit, shared by the D-BRDF and analytic fits.
//
// ceres::Covariance at the solution, by dense SVD with Ceres's null_space_rank = -1: eigenvalues of
// J^T J below 1e-14 of the largest (directions the data do not determine) are dropped instead of
// inverted, so a rank-deficient problem gets the pseudo-inverse rather than infinities. Each
// standard deviation is scaled by sqrt(max(1, chi2/dof)): data that the model explains worse than
// their noise says widen the intervals, data that fit better never narrow them.
#pragma once

#include <optional>
#include <vector>

#include <ceres/problem.h>

namespace zbrdf {

// A parameter block of the problem and its size.
struct ParameterBlock {
  const double* values = nullptr;
  int size = 0;
};

// Standard deviations of every entry of every block (the square roots of the covariance's
// diagonal, inflated as above), in the order given; std::nullopt if Ceres cannot compute the
// covariance.
std::optional<std::vector<std::vector<double>>> ParameterStandardDeviations(
    ceres::Problem& problem, const std::vector<ParameterBlock>& blocks, double chi2_per_dof);

// The condition the fits report when ParameterStandardDeviations gives none.
inline constexpr const char* kUncertaintiesUnavailable =
    "parameter uncertainties unavailable: the problem is rank deficient at the solution (a "
    "parameter the data do not determine)";

}  // namespace zbrdf
