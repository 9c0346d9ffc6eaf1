#include "basis/quadrature.h"

#include <cmath>
#include <string>

#include "basis/error.h"

namespace zbrdf {

GaussLegendreRule GaussLegendre(int n) {
  if (n < 1 || n > 100000) {
    throw InputError("Gauss-Legendre rule needs 1 <= n <= 100000 nodes (got " +
                     std::to_string(n) + ")");
  }
  GaussLegendreRule rule;
  rule.nodes.resize(n);
  rule.weights.resize(n);
  const int half = (n + 1) / 2;
  for (int i = 0; i < half; ++i) {
    // Tricomi's initial guess for the i-th largest root, then Newton on P_n.
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5));
    double dp = 0;
    for (int iter = 0; iter < 100; ++iter) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      const double pn = n == 1 ? x : p1;
      const double pn_1 = n == 1 ? 1.0 : p0;
      dp = n * (x * pn - pn_1) / (x * x - 1.0);
      const double dx = pn / dp;
      x -= dx;
      if (std::abs(dx) <= 1e-16 * std::abs(x) + 1e-300) {
        // One more derivative at the converged root for the weight.
        double q0 = 1.0, q1 = x;
        for (int k = 2; k <= n; ++k) {
          const double q2 = ((2.0 * k - 1.0) * x * q1 - (k - 1.0) * q0) / k;
          q0 = q1;
          q1 = q2;
        }
        dp = n == 1 ? 1.0 : n * (x * q1 - q0) / (x * x - 1.0);
        break;
      }
    }
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    rule.nodes[n - 1 - i] = x;
    rule.nodes[i] = -x;
    rule.weights[n - 1 - i] = w;
    rule.weights[i] = w;
  }
  if (n % 2 == 1) rule.nodes[n / 2] = 0.0;
  return rule;
}

CosThetaRule CosThetaGaussRule(const Zone& zone, int n) {
  const GaussLegendreRule gl = GaussLegendre(n);
  const double a = zone.cos_lower(), b = zone.cos_upper();
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  CosThetaRule rule;
  for (int i = 0; i < n; ++i) {
    const double u = gl.nodes[i];
    const double x = mid + half * u;
    rule.x.push_back(x);
    rule.weight.push_back(half * gl.weights[i]);
    rule.t.push_back(u);
    rule.s_t.push_back(std::sqrt((1.0 - u) * (1.0 + u)));
    rule.s_x.push_back(std::sqrt((1.0 - x) * (1.0 + x)));
  }
  return rule;
}

CosThetaRule CosThetaPsiRule(const Zone& zone, int n) {
  const GaussLegendreRule gl = GaussLegendre(n);
  const double a = zone.cos_lower(), b = zone.cos_upper();
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  CosThetaRule rule;
  for (int i = 0; i < n; ++i) {
    const double psi = 0.5 * M_PI * (1.0 + gl.nodes[i]);
    const double t = std::cos(psi), s = std::sin(psi);
    // 1 - x and 1 + x from the edges, for sqrt(1 - x^2) near the poles.
    const double one_minus_x = (1.0 - b) + half * (1.0 - t);
    const double one_plus_x = (1.0 + a) + half * (1.0 + t);
    rule.x.push_back(mid + half * t);
    rule.weight.push_back(0.5 * M_PI * gl.weights[i] * half * s);
    rule.t.push_back(t);
    rule.s_t.push_back(s);
    rule.s_x.push_back(std::sqrt(one_minus_x * one_plus_x));
  }
  return rule;
}

SphereRule ProductRule(const CosThetaRule& theta_rule, int n_phi) {
  ZBRDF_ASSERT(n_phi >= 1, "n_phi must be positive");
  SphereRule rule;
  const size_t n = theta_rule.x.size();
  rule.directions.reserve(n * n_phi);
  rule.weights.reserve(n * n_phi);
  for (size_t i = 0; i < n; ++i) {
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2.0 * M_PI * j / n_phi;
      const double s = theta_rule.s_x[i];
      rule.directions.push_back({s * std::cos(phi), s * std::sin(phi), theta_rule.x[i]});
      rule.weights.push_back(theta_rule.weight[i] * 2.0 * M_PI / n_phi);
    }
  }
  return rule;
}

}  // namespace zbrdf
