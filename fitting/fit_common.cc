#include "fitting/fit_common.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "basis/error.h"

namespace zbrdf {

FitWeights MakeFitWeights(const std::array<Eigen::VectorXd, 3>& y,
                          const std::array<Eigen::VectorXd, 3>& variance) {
  FitWeights w;
  int non_finite = 0, zero_variance = 0, total = 0;
  double signal = 0, noise = 0, chi2 = 0;
  for (int ch = 0; ch < 3; ++ch) {
    ZBRDF_ASSERT(y[ch].size() == variance[ch].size(), "values and variances differ in size");
    const Eigen::Index n = y[ch].size();
    w.y[ch] = Eigen::VectorXd::Zero(n);
    w.weight[ch] = Eigen::VectorXd::Zero(n);
    double norm2 = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (std::isfinite(y[ch][i]) && std::isfinite(variance[ch][i])) norm2 += y[ch][i] * y[ch][i];
    }
    const double floor2 = kModelErrorFloor * kModelErrorFloor * norm2;
    for (Eigen::Index i = 0; i < n; ++i) {
      ++total;
      const double v = y[ch][i], var = variance[ch][i];
      if (!std::isfinite(v) || !std::isfinite(var) || var < 0) {
        ++non_finite;
        continue;
      }
      if (var == 0) ++zero_variance;
      const double sigma2 = var + floor2;
      w.y[ch][i] = v;
      signal += v * v;
      noise += var;
      if (sigma2 > 0) {
        w.weight[ch][i] = 1.0 / std::sqrt(sigma2);
        chi2 += v * v / sigma2;
        ++w.used;
      }
    }
  }
  char text[200];
  if (non_finite > 0) {
    std::snprintf(text, sizeof(text),
                  "%d of %d coefficients are not finite (damaged data); they were left out",
                  non_finite, total);
    w.conditions.push_back(text);
  }
  if (zero_variance == total - non_finite && total > non_finite) {
    std::snprintf(text, sizeof(text),
                  "the data carry no variances (noise-free or unprocessed); every coefficient is "
                  "weighted by the model-error floor %.0e of the tensor norm",
                  kModelErrorFloor);
    w.conditions.push_back(text);
  }
  w.signal_to_noise = noise > 0 ? std::sqrt(signal / noise) : (signal > 0 ? INFINITY : 0.0);
  // Signal: sum y^2 / sigma^2 is chi-square with `used` degrees of freedom when y is pure noise;
  // ask for 5 standard deviations above its mean.
  w.any_signal = w.used > 0 && chi2 > w.used + 5.0 * std::sqrt(2.0 * w.used);
  if (!w.any_signal) {
    w.conditions.push_back(
        signal == 0 ? "the data are all zero: nothing was measured (black sample, no light, or every "
                      "pixel saturated and dropped)"
                    : "the data hold no signal above their noise: nothing to fit");
  }
  return w;
}

FitStatistics ComputeFitStatistics(const FitWeights& w, const std::array<Eigen::VectorXd, 3>& model,
                                   int parameters) {
  FitStatistics s;
  double diff = 0, norm = 0;
  for (int ch = 0; ch < 3; ++ch) {
    for (Eigen::Index i = 0; i < w.y[ch].size(); ++i) {
      if (w.weight[ch][i] <= 0) continue;
      const double d = model[ch][i] - w.y[ch][i];
      s.chi2 += d * d * w.weight[ch][i] * w.weight[ch][i];
      diff += d * d;
      norm += w.y[ch][i] * w.y[ch][i];
      ++s.residuals;
    }
  }
  s.parameters = parameters;
  s.chi2_per_dof = s.chi2 / std::max(1, s.residuals - parameters);
  s.relative_residual = norm > 0 ? std::sqrt(diff / norm) : 0.0;
  return s;
}

double GgxD(double alpha, double theta_h_rad) {
  const double c = std::cos(theta_h_rad);
  if (c <= 0) return 0.0;
  const double t = std::tan(theta_h_rad);
  const double a2 = alpha * alpha;
  const double denom = a2 + t * t;
  return a2 / (M_PI * c * c * c * c * denom * denom);
}

double MinimizeScalar(const std::function<double(double)>& f, double lo, double hi, int scan,
                      int iterations) {
  ZBRDF_ASSERT(hi > lo && scan >= 3, "bad bracket");
  int best = 0;
  double best_value = INFINITY;
  std::vector<double> values(scan);
  for (int i = 0; i < scan; ++i) {
    values[i] = f(lo + (hi - lo) * i / (scan - 1));
    if (values[i] < best_value || !std::isfinite(best_value)) {
      best_value = values[i];
      best = i;
    }
  }
  double a = lo + (hi - lo) * std::max(0, best - 1) / (scan - 1);
  double b = lo + (hi - lo) * std::min(scan - 1, best + 1) / (scan - 1);
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = b - g * (b - a), x2 = a + g * (b - a);
  double f1 = f(x1), f2 = f(x2);
  for (int it = 0; it < iterations; ++it) {
    if (f1 < f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - g * (b - a);
      f1 = f(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + g * (b - a);
      f2 = f(x2);
    }
  }
  const double x = 0.5 * (a + b);
  const double grid = lo + (hi - lo) * best / (scan - 1);
  return f(x) <= best_value ? x : grid;
}

Eigen::VectorXd NonNegativeLeastSquares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b) {
  const int n = static_cast<int>(a.cols());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<bool> passive(n, false);
  const double tol = 1e-12 * std::max(1.0, a.norm() * b.norm());
  for (int outer = 0; outer < 3 * n + 3; ++outer) {
    const Eigen::VectorXd gradient = a.transpose() * (b - a * x);
    int best = -1;
    double best_g = tol;
    for (int j = 0; j < n; ++j) {
      if (!passive[j] && gradient[j] > best_g) {
        best_g = gradient[j];
        best = j;
      }
    }
    if (best < 0) break;
    passive[best] = true;
    for (int inner = 0; inner < 3 * n + 3; ++inner) {
      std::vector<int> p;
      for (int j = 0; j < n; ++j) {
        if (passive[j]) p.push_back(j);
      }
      Eigen::MatrixXd ap(a.rows(), p.size());
      for (size_t k = 0; k < p.size(); ++k) ap.col(k) = a.col(p[k]);
      const Eigen::VectorXd zp = ap.colPivHouseholderQr().solve(b);
      Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
      for (size_t k = 0; k < p.size(); ++k) z[p[k]] = zp[k];
      bool feasible = true;
      for (int j : p) feasible = feasible && z[j] > 0;
      if (feasible) {
        x = z;
        break;
      }
      double step = 1.0;
      for (int j : p) {
        if (z[j] <= 0) step = std::min(step, x[j] / (x[j] - z[j]));
      }
      x += step * (z - x);
      for (int j : p) {
        if (x[j] <= 1e-15 * std::max(1.0, x.cwiseAbs().maxCoeff())) {
          x[j] = 0;
          passive[j] = false;
        }
      }
    }
  }
  return x;
}

}  // namespace zbrdf
