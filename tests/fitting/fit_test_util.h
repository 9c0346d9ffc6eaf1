// Shared references for the fitting tests: a brute-force zonal projection (product rules over
// both directions, independent of fit_quadrature.h's half-vector rule) and synthetic zonal data.
#pragma once

#include <array>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "basis/parallel.h"
#include "basis/quadrature.h"
#include "basis/zonal_basis.h"
#include "brdf/brdf.h"
#include "brdf/dbrdf.h"
#include "brdf/ggx.h"
#include "fitting/fit_data.h"

namespace zbrdf::testing {

// z_kj = sum over a product rule in w_i and in w_r (n_theta psi nodes x n_phi trapezoid points
// each) of Z_k(w_i) Z_j(w_r) f_r cos(theta_i). Converges like the psi rule on the smooth parts
// and like O(h^2) on the kinks of tabulated models.
inline std::array<Eigen::MatrixXd, 3> BruteForceTensor(const Brdf& brdf, const Zone& zone,
                                                       int order, int n_theta, int n_phi) {
  const SphereRule rule = ProductRule(CosThetaPsiRule(zone, n_theta), n_phi);
  const ZonalBasis zb(zone, order);
  const int n = zb.size(), q = static_cast<int>(rule.weights.size());
  Eigen::MatrixXd z(q, n);
  std::vector<double> row(n);
  for (int i = 0; i < q; ++i) {
    zb.Eval(rule.directions[i], row.data());
    for (int k = 0; k < n; ++k) z(i, k) = row[k];
  }
  std::array<Eigen::MatrixXd, 3> f;
  for (auto& m : f) m.resize(q, q);
  ParallelFor(q, 16, [&](int64_t i0, int64_t i1) {
    for (int64_t i = i0; i < i1; ++i) {
      for (int j = 0; j < q; ++j) {
        const Rgb v = brdf.Eval(rule.directions[i], rule.directions[j]) *
                      (rule.directions[i].z * rule.weights[i] * rule.weights[j]);
        for (int ch = 0; ch < 3; ++ch) f[ch](i, j) = v[ch];
      }
    }
  });
  std::array<Eigen::MatrixXd, 3> out;
  for (int ch = 0; ch < 3; ++ch) out[ch] = z.transpose() * f[ch] * z;
  return out;
}

// Zonal data from tensors with the given per-coefficient standard deviation, relative to each
// channel's RMS coefficient, and matching Gaussian noise (fixed seed); 0: exact data with zero
// variances.
inline ZonalTensor SyntheticData(const std::array<Eigen::MatrixXd, 3>& tensor, const Zone& zone,
                                 int order, double relative_sigma = 0, uint64_t seed = 7) {
  ZonalTensor data;
  data.theta_min_rad = zone.theta_min_rad();
  data.theta_max_rad = zone.theta_max_rad();
  data.order = order;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  for (int ch = 0; ch < 3; ++ch) {
    const double rms = std::sqrt(tensor[ch].squaredNorm() / tensor[ch].size());
    const double sigma = relative_sigma * rms;
    data.z[ch] = tensor[ch];
    data.variance[ch] = Eigen::MatrixXd::Constant(tensor[ch].rows(), tensor[ch].cols(), sigma * sigma);
    if (sigma > 0) {
      for (Eigen::Index i = 0; i < data.z[ch].size(); ++i) data.z[ch].data()[i] += sigma * normal(rng);
    }
  }
  return data;
}

// A D-BRDF whose p(h) is GGX's D (alpha_x, alpha_y) tabulated on theta_samples x phi_samples
// nodes and normalized, with the given colours.
inline DBrdfParams GgxShapedDBrdf(double alpha_x, double alpha_y, int theta_samples, int phi_samples,
                                  const Rgb& c, double f0, const Rgb& kd) {
  const GgxBrdf ggx(alpha_x, alpha_y, Rgb(0.5), Rgb(0.0));
  DBrdfParams params;
  params.p_h.theta_samples = theta_samples;
  params.p_h.phi_samples = phi_samples;
  for (int j = 0; j < theta_samples; ++j) {
    for (int k = 0; k < phi_samples; ++k) {
      params.p_h.p.push_back(
          ggx.D(SphericalDirection(j * 0.5 * M_PI / (theta_samples - 1), k * 2 * M_PI / phi_samples)));
    }
  }
  params.p_h.Normalize();
  params.c = c;
  params.f0 = f0;
  params.kd = kd;
  return params;
}

}  // namespace zbrdf::testing
