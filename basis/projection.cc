#include "basis/projection.h"

#include <vector>

#include "basis/quadrature.h"

namespace zbrdf {

Eigen::VectorXd ProjectOntoZonalBasis(const ZonalBasis& zb,
                                      const std::function<double(const Vec3&)>& g, int n_psi,
                                      int n_phi) {
  const SphereRule rule = ProductRule(CosThetaPsiRule(zb.zone(), n_psi), n_phi);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(zb.size());
  std::vector<double> values(zb.size());
  for (size_t q = 0; q < rule.weights.size(); ++q) {
    const double weighted = rule.weights[q] * g(rule.directions[q]);
    if (weighted == 0) continue;
    zb.Eval(rule.directions[q], values.data());
    for (int j = 0; j < zb.size(); ++j) z(j) += weighted * values[j];
  }
  return z;
}

}  // namespace zbrdf
