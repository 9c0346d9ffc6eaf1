#include "fitting/covariance.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <ceres/covariance.h>

namespace zbrdf {

std::optional<std::vector<std::vector<double>>> ParameterStandardDeviations(
    ceres::Problem& problem, const std::vector<ParameterBlock>& blocks, double chi2_per_dof) {
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::DENSE_SVD;
  options.null_space_rank = -1;
  options.min_reciprocal_condition_number = 1e-14;
  ceres::Covariance covariance(options);
  std::vector<std::pair<const double*, const double*>> pairs;
  for (const ParameterBlock& b : blocks) pairs.emplace_back(b.values, b.values);
  if (!covariance.Compute(pairs, &problem)) return std::nullopt;
  const double inflate = std::max(1.0, chi2_per_dof);
  std::vector<std::vector<double>> deviations;
  for (const ParameterBlock& b : blocks) {
    std::vector<double> c(static_cast<size_t>(b.size) * b.size);
    if (!covariance.GetCovarianceBlock(b.values, b.values, c.data())) return std::nullopt;
    std::vector<double>& d = deviations.emplace_back(b.size);
    for (int i = 0; i < b.size; ++i) d[i] = std::sqrt(std::max(0.0, c[i * (b.size + 1)] * inflate));
  }
  return deviations;
}

}  // namespace zbrdf
