#include "basis/gram.h"

#include <array>
#include <cmath>

#include "basis/error.h"
#include "basis/legendre.h"
#include "basis/quadrature.h"

namespace zbrdf {

Eigen::MatrixXd TargetGramBlock(const TargetBasis& target, const Zone& zone, int abs_m) {
  const int n = static_cast<int>(target.DegreesForOrder(abs_m).size());
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(n, n);
  if (n == 0) return gram;
  // Products of two theta factors are polynomials in x of degree <= 2 * order.
  const CosThetaRule rule = CosThetaGaussRule(zone, target.order() + 2);
  Eigen::VectorXd f(n);
  for (size_t q = 0; q < rule.x.size(); ++q) {
    target.EvalThetaFactor(abs_m, rule.x[q], rule.s_x[q], f.data());
    gram.noalias() += (2.0 * M_PI * rule.weight[q]) * f * f.transpose();
  }
  return gram;
}

Eigen::MatrixXd MixedBlock(const TargetBasis& target, const ZonalBasis& zb, int abs_m,
                           int psi_nodes) {
  const int n_target = static_cast<int>(target.DegreesForOrder(abs_m).size());
  const int n_zb = abs_m <= zb.order() ? zb.order() - abs_m + 1 : 0;
  Eigen::MatrixXd block = Eigen::MatrixXd::Zero(n_target, n_zb);
  if (n_target == 0 || n_zb == 0) return block;
  const CosThetaRule rule = CosThetaPsiRule(zb.zone(), psi_nodes);
  Eigen::VectorXd f(n_target), g(n_zb);
  for (size_t q = 0; q < rule.x.size(); ++q) {
    target.EvalThetaFactor(abs_m, rule.x[q], rule.s_x[q], f.data());
    NormalizedLegendreOrder(zb.order(), abs_m, rule.t[q], rule.s_t[q], g.data());
    block.noalias() += (2.0 * M_PI * rule.weight[q] * zb.normalization()) * f * g.transpose();
  }
  return block;
}

int DefaultPsiNodes(int target_order, int zb_order) {
  return 2 * (target_order + zb_order) + 40;
}

Eigen::MatrixXd ZonalGramByQuadrature(const ZonalBasis& zb, int n_theta, int n_phi) {
  const SphereRule rule = ProductRule(CosThetaGaussRule(zb.zone(), n_theta), n_phi);
  const int n = zb.size();
  const int nodes = static_cast<int>(rule.weights.size());
  Eigen::MatrixXd values(nodes, n);  // row q: sqrt(w_q) Z(direction_q)
  std::vector<double> z(n);
  for (int q = 0; q < nodes; ++q) {
    zb.Eval(rule.directions[q], z.data());
    const double root_w = std::sqrt(rule.weights[q]);
    for (int k = 0; k < n; ++k) values(q, k) = root_w * z[k];
  }
  return values.transpose() * values;
}

}  // namespace zbrdf
