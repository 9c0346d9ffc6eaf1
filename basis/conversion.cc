#include "basis/conversion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "basis/error.h"
#include "basis/gram.h"
#include "basis/spherical_harmonics.h"

namespace zbrdf {

ZonalToTarget::ZonalToTarget(const ZonalBasis& zb, const TargetBasis& target, double tau)
    : zb_(zb), target_(target) {
  if (!(tau >= 0 && tau < 1)) {
    throw InputError("truncation threshold tau must be in [0, 1) (got " + std::to_string(tau) +
                     ")");
  }
  const int n_target = target.size(), n_zb = zb.size();
  conversion_ = Eigen::MatrixXd::Zero(n_target, n_zb);
  moments_ = Eigen::MatrixXd::Zero(n_zb, n_target);
  const int psi_nodes = DefaultPsiNodes(target.order(), zb.order());
  const int max_m = std::max(target.order(), zb.order());

  double sigma_max = 0;
  std::vector<Eigen::MatrixXd> moment_blocks;
  std::vector<Eigen::JacobiSVD<Eigen::MatrixXd>> svds;
  for (int abs_m = 0; abs_m <= max_m; ++abs_m) {
    Block block;
    block.abs_m = abs_m;
    block.target_degrees = target.DegreesForOrder(abs_m);
    Eigen::MatrixXd moment = MixedBlock(target, zb, abs_m, psi_nodes).transpose();
    Eigen::JacobiSVD<Eigen::MatrixXd> svd;
    if (moment.size() > 0) {
      svd.compute(moment, Eigen::ComputeThinU | Eigen::ComputeThinV);
      if (svd.singularValues().size() > 0) {
        sigma_max = std::max(sigma_max, svd.singularValues()(0));
      }
    }
    blocks_.push_back(std::move(block));
    moment_blocks.push_back(std::move(moment));
    svds.push_back(std::move(svd));
  }
  if (!(sigma_max > 0)) throw NumericalError("zonal-to-target moment matrix is zero");

  diagnostics_.tau = tau;
  diagnostics_.largest_singular_value = sigma_max;
  double sigma_min_kept = std::numeric_limits<double>::infinity();
  const double cutoff = tau * sigma_max;
  for (size_t b = 0; b < blocks_.size(); ++b) {
    Block& block = blocks_[b];
    const Eigen::MatrixXd& moment = moment_blocks[b];
    const int multiplicity = block.abs_m == 0 ? 1 : 2;
    // Target functions with no ZB moment to determine them (more unknowns than moments).
    if (moment.cols() > moment.rows()) {
      diagnostics_.underdetermined_components +=
          multiplicity * static_cast<int>(moment.cols() - moment.rows());
    }
    if (moment.size() == 0) continue;
    const auto& sv = svds[b].singularValues();
    block.u = svds[b].matrixU();
    block.v = svds[b].matrixV();
    block.inverse_sigma = Eigen::VectorXd::Zero(sv.size());
    for (int i = 0; i < sv.size(); ++i) {
      for (int k = 0; k < multiplicity; ++k) diagnostics_.singular_values.push_back(sv(i));
      if (sv(i) > cutoff && sv(i) > 0) {
        block.inverse_sigma(i) = 1.0 / sv(i);
        sigma_min_kept = std::min(sigma_min_kept, sv(i));
      } else {
        diagnostics_.truncated_components += multiplicity;
      }
    }
    const Eigen::MatrixXd pinv =
        block.v * block.inverse_sigma.asDiagonal() * block.u.transpose();
    // Scatter into the full matrices for +m (cos) and -m (sin).
    for (int sign : {+1, -1}) {
      if (block.abs_m == 0 && sign < 0) continue;
      const int m = sign * block.abs_m;
      for (size_t i = 0; i < block.target_degrees.size(); ++i) {
        const int row = target.Index(block.target_degrees[i], m);
        for (int j = 0; j < moment.rows(); ++j) {
          const int col = ShIndex(block.abs_m + j, m);
          conversion_(row, col) = pinv(i, j);
          moments_(col, row) = moment(j, i);
        }
      }
    }
  }
  std::sort(diagnostics_.singular_values.rbegin(), diagnostics_.singular_values.rend());
  diagnostics_.smallest_kept_singular_value = sigma_min_kept;
  diagnostics_.noise_gain = std::isfinite(sigma_min_kept) ? 1.0 / sigma_min_kept : 0.0;
}

Eigen::VectorXd ZonalToTarget::Apply(const Eigen::VectorXd& z) const {
  if (z.size() != zb_.size()) {
    throw InputError("zonal coefficient vector has " + std::to_string(z.size()) +
                     " entries, expected " + std::to_string(zb_.size()) + " (order " +
                     std::to_string(zb_.order()) + ")");
  }
  Eigen::VectorXd y = Eigen::VectorXd::Zero(target_.size());
  for (const Block& block : blocks_) {
    if (block.u.size() == 0) continue;
    for (int sign : {+1, -1}) {
      if (block.abs_m == 0 && sign < 0) continue;
      const int m = sign * block.abs_m;
      Eigen::VectorXd z_m(block.u.rows());
      for (int j = 0; j < z_m.size(); ++j) z_m(j) = z(ShIndex(block.abs_m + j, m));
      const Eigen::VectorXd w = block.inverse_sigma.cwiseProduct(block.u.transpose() * z_m);
      const Eigen::VectorXd y_m = block.v * w;
      for (size_t i = 0; i < block.target_degrees.size(); ++i) {
        y(target_.Index(block.target_degrees[i], m)) = y_m(i);
      }
    }
  }
  return y;
}

Eigen::MatrixXd ZonalToTarget::ApplyToColumns(const Eigen::MatrixXd& z) const {
  Eigen::MatrixXd y(target_.size(), z.cols());
  for (int c = 0; c < z.cols(); ++c) y.col(c) = Apply(Eigen::VectorXd(z.col(c)));
  return y;
}

Eigen::MatrixXd ConvertTensor(const ZonalToTarget& incident, const ZonalToTarget& exitant,
                              const Eigen::MatrixXd& z) {
  if (z.rows() != incident.zonal_basis().size() || z.cols() != exitant.zonal_basis().size()) {
    throw InputError("tensor coefficients are " + std::to_string(z.rows()) + " x " +
                     std::to_string(z.cols()) + ", expected " +
                     std::to_string(incident.zonal_basis().size()) + " x " +
                     std::to_string(exitant.zonal_basis().size()));
  }
  // Y = C_i Z C_r^T = (C_r (C_i Z)^T)^T, each product in factored form.
  const Eigen::MatrixXd half = incident.ApplyToColumns(z);
  return exitant.ApplyToColumns(half.transpose()).transpose();
}

}  // namespace zbrdf
