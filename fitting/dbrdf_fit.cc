#include "fitting/dbrdf_fit.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <mutex>

#include <ceres/ceres.h>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/spherical_harmonics.h"
#include "basis/stopwatch.h"
#include "basis/zonal_basis.h"
#include "fitting/covariance.h"

namespace zbrdf {
namespace {

std::mutex& ProjectionMutex() {
  static std::mutex m;
  return m;
}

// Weights w_j with integral p(h) cos(theta_h) dw_h = sum_j w_j p_j for a table of the given size
// (HalfVectorTable::NormalizationIntegral is linear in p).
Eigen::VectorXd NormalizationWeights(int theta_samples, int phi_samples) {
  const int size = theta_samples * phi_samples;
  Eigen::VectorXd w(size);
  HalfVectorTable unit;
  unit.theta_samples = theta_samples;
  unit.phi_samples = phi_samples;
  unit.p.assign(size, 0.0);
  for (int i = 0; i < size; ++i) {
    unit.p[i] = 1.0;
    w[i] = unit.NormalizationIntegral();
    unit.p[i] = 0.0;
  }
  return w;
}

// Knot positions (table node indices) up to last_node: spacing max(2, min(6, theta / 4)) deg,
// about what order-8 to 10 data resolve near the specular peak.
std::vector<int> KnotNodes(int theta_samples, int last_node) {
  const double step_deg = 90.0 / (theta_samples - 1);
  std::vector<int> knots{0};
  while (knots.back() < last_node) {
    const double theta = knots.back() * step_deg;
    const double spacing = std::max(2.0, std::min(6.0, theta / 4.0));
    int next = knots.back() + std::max(1, static_cast<int>(std::lround(spacing / step_deg)));
    next = std::min(next, last_node);
    if (last_node - next > 0 && (last_node - next) * step_deg < 0.5 * spacing) next = last_node;
    knots.push_back(next);
  }
  return knots;
}

// The linear map from free parameters q to table values p (table nodes x parameters). p follows
// a prior shape s(theta) (the fitted GGX lobe) modulated by a ratio interpolated linearly between
// knots: p(theta) = s(theta) ((1 - t) q_k / s_k + t q_k+1 / s_k+1), so the fine structure near
// the peak, which the data do not resolve, keeps the physical lobe's shape, while the knots move
// its coarse course. Beyond the last knot the ratio is held (the GGX tail). The theta = 0 knot is
// shared by every phi (p is continuous at the pole).
Eigen::MatrixXd TableMap(int theta_samples, int phi_samples, const std::vector<int>& knots,
                         double tail_alpha) {
  const double step = 0.5 * M_PI / (theta_samples - 1);
  const int nk = static_cast<int>(knots.size());
  const int params = 1 + (nk - 1) * phi_samples;
  auto param = [&](int knot, int k) { return knot == 0 ? 0 : 1 + (knot - 1) * phi_samples + k; };
  auto shape = [&](int node) { return std::max(GgxD(tail_alpha, node * step), 1e-300); };
  Eigen::MatrixXd map = Eigen::MatrixXd::Zero(theta_samples * phi_samples, params);
  const int last = knots.back();
  for (int j = 0; j < theta_samples; ++j) {
    for (int k = 0; k < phi_samples; ++k) {
      const int row = j * phi_samples + k;
      if (j >= last) {
        map(row, param(nk - 1, k)) = GgxD(tail_alpha, j * step) / shape(last);
        continue;
      }
      int s = 0;
      while (knots[s + 1] <= j) ++s;
      const double t = static_cast<double>(j - knots[s]) / (knots[s + 1] - knots[s]);
      const double here = GgxD(tail_alpha, j * step);
      map(row, param(s, k)) += (1.0 - t) * here / shape(knots[s]);
      if (t > 0) map(row, param(s + 1, k)) += t * here / shape(knots[s + 1]);
    }
  }
  return map;
}

// Second differences of the ratio r = p / s (s: the GGX shape TableMap modulates) at the knots,
// along theta for each phi, in x = theta / theta_last_knot, each scaled so that the sum of squares
// approximates the integral of r''(x)^2 dx. Rows x parameters; the parameters are p at the knots.
Eigen::MatrixXd RatioCurvature(int theta_samples, int phi_samples, const std::vector<int>& knots,
                               double tail_alpha) {
  const double step = 0.5 * M_PI / (theta_samples - 1);
  const int nk = static_cast<int>(knots.size());
  const int params = 1 + (nk - 1) * phi_samples;
  auto param = [&](int knot, int k) { return knot == 0 ? 0 : 1 + (knot - 1) * phi_samples + k; };
  auto inv_shape = [&](int knot) { return 1.0 / std::max(GgxD(tail_alpha, knots[knot] * step), 1e-300); };
  const double x_scale = 1.0 / std::max(1, knots.back());
  auto x = [&](int knot) { return knots[knot] * x_scale; };
  std::vector<Eigen::RowVectorXd> rows;
  for (int k = 0; k < phi_samples; ++k) {
    for (int a = 1; a + 1 < nk; ++a) {
      Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(params);
      const double h0 = x(a) - x(a - 1), h1 = x(a + 1) - x(a), hm = 0.5 * (h0 + h1);
      const double scale = std::sqrt(hm) / hm;
      row[param(a + 1, k)] += scale * inv_shape(a + 1) / h1;
      row[param(a, k)] -= scale * inv_shape(a) * (1.0 / h0 + 1.0 / h1);
      row[param(a - 1, k)] += scale * inv_shape(a - 1) / h0;
      rows.push_back(row);
    }
  }
  Eigen::MatrixXd m(rows.size(), params);
  for (size_t i = 0; i < rows.size(); ++i) m.row(static_cast<Eigen::Index>(i)) = rows[i];
  return m;
}

// Psi-rule nodes per direction for the fitter's quadrature (fit_quadrature.h): the quadrature's
// default (2 order + 32), but at least two per degree of the zone's width. A table node's hat
// function has kinks where the range of theta_h over Delta, from |theta_i - theta_r| / 2 to
// (theta_i + theta_r) / 2, crosses the neighbouring nodes: lines 2 deg apart in the
// (theta_i, theta_r) plane, which a product rule integrates only to O(spacing^2). Measured on the
// fast thesis zone at order 8 (against 320 nodes): the projection of the theta_h = 0 node is 2.6%
// off with the default 48 nodes, 0.5% with 96; the other nodes 0.1-0.8% and 0.01-0.09%. At order 4
// on the full preset's zone (40 nodes by default) the theta_h = 0 node was 13% off, and a 3 deg
// lobe came back with kd 8% and c F0 4% off (0.05% and 0.09% with 94 nodes).
int DefaultThetaNodes(const Zone& zone, int order) {
  const double width_deg = (zone.theta_max_rad() - zone.theta_min_rad()) * 180.0 / M_PI;
  return std::max(2 * order + 32, static_cast<int>(std::ceil(2.0 * width_deg)));
}

// The fit's linear pieces in parameter space.
struct Problem {
  FitWeights w;
  Eigen::MatrixXd nq, rq;    // coefficients x parameters: normal and grazing parts
  Eigen::VectorXd diffuse;   // coefficients
  Eigen::RowVectorXd norm;   // normalization integral per parameter
  double norm_weight = 1;
  // Smoothness penalty rows (penalty x parameters), residuals penalty * q; empty: none.
  Eigen::MatrixXd penalty;
};

class DBrdfCost final : public ceres::CostFunction {
 public:
  explicit DBrdfCost(const Problem& p) : p_(p) {
    set_num_residuals(3 * static_cast<int>(p.diffuse.size()) + 1 + static_cast<int>(p.penalty.rows()));
    mutable_parameter_block_sizes()->assign({static_cast<int>(p.nq.cols()), 1, 3, 3});
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int nq = static_cast<int>(p_.nq.cols());
    const Eigen::Index n = p_.diffuse.size();
    const Eigen::Map<const Eigen::VectorXd> q(parameters[0], nq);
    const double f0 = parameters[1][0];
    const double* c = parameters[2];
    const double* kd = parameters[3];
    const Eigen::VectorXd np = p_.nq * q, rp = p_.rq * q;
    for (int ch = 0; ch < 3; ++ch) {
      const Eigen::VectorXd& w = p_.w.weight[ch];
      for (Eigen::Index i = 0; i < n; ++i) {
        const double model = c[ch] * (f0 * np[i] + rp[i]) + kd[ch] * p_.diffuse[i];
        residuals[ch * n + i] = w[i] * (model - p_.w.y[ch][i]);
      }
    }
    residuals[3 * n] = p_.norm_weight * (p_.norm.dot(q) - 1.0);
    const Eigen::Index np_rows = p_.penalty.rows();
    if (np_rows > 0) Eigen::Map<Eigen::VectorXd>(residuals + 3 * n + 1, np_rows) = p_.penalty * q;
    if (!jacobians) return true;
    const int rows = static_cast<int>(3 * n + 1 + np_rows);
    if (jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> j(
          jacobians[0], rows, nq);
      for (int ch = 0; ch < 3; ++ch) {
        j.middleRows(ch * n, n) =
            p_.w.weight[ch].asDiagonal() * (c[ch] * (f0 * p_.nq + p_.rq));
      }
      j.row(3 * n) = p_.norm_weight * p_.norm;
      if (np_rows > 0) j.bottomRows(np_rows) = p_.penalty;
    }
    if (jacobians[1]) {
      for (int ch = 0; ch < 3; ++ch) {
        for (Eigen::Index i = 0; i < n; ++i) jacobians[1][ch * n + i] = p_.w.weight[ch][i] * c[ch] * np[i];
      }
      for (Eigen::Index r = 3 * n; r < rows; ++r) jacobians[1][r] = 0;
    }
    for (int block = 2; block <= 3; ++block) {
      if (!jacobians[block]) continue;
      std::fill(jacobians[block], jacobians[block] + rows * 3, 0.0);
      for (int ch = 0; ch < 3; ++ch) {
        for (Eigen::Index i = 0; i < n; ++i) {
          const double d = block == 2 ? f0 * np[i] + rp[i] : p_.diffuse[i];
          jacobians[block][(ch * n + i) * 3 + ch] = p_.w.weight[ch][i] * d;
        }
      }
    }
    return true;
  }

 private:
  const Problem& p_;
};

struct Solution {
  Eigen::VectorXd q;
  double f0 = 0.5;
  Rgb c, kd;
};

std::array<Eigen::VectorXd, 3> Predict(const Problem& p, const Solution& s) {
  const Eigen::VectorXd np = p.nq * s.q, rp = p.rq * s.q;
  std::array<Eigen::VectorXd, 3> out;
  for (int ch = 0; ch < 3; ++ch) out[ch] = s.c[ch] * (s.f0 * np + rp) + s.kd[ch] * p.diffuse;
  return out;
}

double Chi2(const Problem& p, const Solution& s) {
  const auto m = Predict(p, s);
  double chi2 = 0;
  for (int ch = 0; ch < 3; ++ch) chi2 += (p.w.weight[ch].cwiseProduct(m[ch] - p.w.y[ch])).squaredNorm();
  return chi2;
}

// Best (c F0, c, kd) per channel for fixed p columns by NNLS; F0 shared: the channel-weighted
// ratio. Returns chi2.
double SolveLinear(const FitWeights& w, const Eigen::VectorXd& np, const Eigen::VectorXd& rp,
                   const Eigen::VectorXd& diffuse, Solution* s) {
  double sum_a1 = 0, sum_a2 = 0;
  Eigen::Vector3d x[3];
  for (int ch = 0; ch < 3; ++ch) {
    Eigen::MatrixXd a(np.size(), 3);
    a.col(0) = w.weight[ch].cwiseProduct(np);
    a.col(1) = w.weight[ch].cwiseProduct(rp);
    a.col(2) = w.weight[ch].cwiseProduct(diffuse);
    x[ch] = NonNegativeLeastSquares(a, w.weight[ch].cwiseProduct(w.y[ch]));
    sum_a1 += x[ch][0];
    sum_a2 += x[ch][1];
  }
  // c F0 = a1, c = a2 would need a1 <= a2; keep a1 (the part the zone measures well) and set
  // F0 from the channel sums.
  s->f0 = sum_a2 > 0 ? sum_a1 / sum_a2 : 1.0;
  for (int ch = 0; ch < 3; ++ch) {
    s->c[ch] = s->f0 > 0 ? x[ch][0] / s->f0 : 0.0;
    s->kd[ch] = x[ch][2];  // the diffuse column is the projection of cos / pi: albedo units
  }
  double chi2 = 0;
  for (int ch = 0; ch < 3; ++ch) {
    const Eigen::VectorXd m = s->c[ch] * (s->f0 * np + rp) + s->kd[ch] * diffuse;
    chi2 += w.weight[ch].cwiseProduct(m - w.y[ch]).squaredNorm();
  }
  return chi2;
}

// Weighted Gram matrices of the model's columns and of the data, per channel: with them every
// sub-problem of the alternating solver (step 4) is a small quadratic form.
struct Grams {
  std::array<Eigen::MatrixXd, 3> nn, nr, rr;      // parameters x parameters
  std::array<Eigen::VectorXd, 3> nd, rd, ny, ry;  // parameters
  std::array<double, 3> dd{}, dy{}, yy{};
};

Grams MakeGrams(const Problem& p) {
  Grams g;
  for (int ch = 0; ch < 3; ++ch) {
    const Eigen::VectorXd& w = p.w.weight[ch];
    const Eigen::MatrixXd nw = w.asDiagonal() * p.nq, rw = w.asDiagonal() * p.rq;
    const Eigen::VectorXd dw = w.cwiseProduct(p.diffuse), yw = w.cwiseProduct(p.w.y[ch]);
    g.nn[ch] = nw.transpose() * nw;
    g.nr[ch] = nw.transpose() * rw;
    g.rr[ch] = rw.transpose() * rw;
    g.nd[ch] = nw.transpose() * dw;
    g.rd[ch] = rw.transpose() * dw;
    g.ny[ch] = nw.transpose() * yw;
    g.ry[ch] = rw.transpose() * yw;
    g.dd[ch] = dw.squaredNorm();
    g.dy[ch] = dw.dot(yw);
    g.yy[ch] = yw.squaredNorm();
  }
  return g;
}

// min x^T H x / 2 - g^T x subject to x >= 0, H symmetric positive semi-definite: the active-set
// method of Lawson & Hanson (1974, ch. 23) on the normal equations, warm-started from the support
// of x. A relative ridge of 1e-13 on H's diagonal keeps the passive systems solvable when H is
// singular (unresolved knots); it changes the objective by less than rounding.
Eigen::VectorXd NonNegativeQuadratic(const Eigen::MatrixXd& h, const Eigen::VectorXd& g,
                                     Eigen::VectorXd x) {
  const Eigen::Index n = g.size();
  std::vector<char> passive(n, 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (x[i] > 0) {
      passive[i] = 1;
    } else {
      x[i] = 0;
    }
  }
  const double tol = 1e-12 * std::max(g.cwiseAbs().maxCoeff(), 1e-300);
  auto solve_passive = [&](std::vector<Eigen::Index>* idx) {
    idx->clear();
    for (Eigen::Index i = 0; i < n; ++i) {
      if (passive[i]) idx->push_back(i);
    }
    const Eigen::Index k = static_cast<Eigen::Index>(idx->size());
    Eigen::MatrixXd hp(k, k);
    Eigen::VectorXd gp(k);
    for (Eigen::Index a = 0; a < k; ++a) {
      gp[a] = g[(*idx)[a]];
      for (Eigen::Index b = 0; b < k; ++b) hp(a, b) = h((*idx)[a], (*idx)[b]);
      hp(a, a) += 1e-13 * std::abs(hp(a, a)) + 1e-300;
    }
    return Eigen::VectorXd(hp.ldlt().solve(gp));
  };
  std::vector<Eigen::Index> idx;
  for (int outer = 0; outer < 4 * n + 20; ++outer) {
    // Solve on the passive set; step back toward feasibility while some value is not positive.
    for (int inner = 0; inner <= n; ++inner) {
      const Eigen::VectorXd z = solve_passive(&idx);
      if (idx.empty()) break;
      double alpha = 1.0;
      Eigen::Index blocking = -1;
      for (size_t a = 0; a < idx.size(); ++a) {
        if (z[a] <= 0) {
          const double xi = x[idx[a]];
          const double t = xi / (xi - z[a]);
          if (t < alpha) {
            alpha = t;
            blocking = idx[a];
          }
        }
      }
      for (size_t a = 0; a < idx.size(); ++a) x[idx[a]] += alpha * (z[a] - x[idx[a]]);
      if (blocking < 0) break;
      x[blocking] = 0;
      for (size_t a = 0; a < idx.size(); ++a) {
        if (x[idx[a]] <= 0) {
          x[idx[a]] = 0;
          passive[idx[a]] = 0;
        }
      }
      passive[blocking] = 0;
    }
    // Optimal when no value at 0 would lower the objective by growing.
    const Eigen::VectorXd gradient = g - h * x;
    Eigen::Index best = -1;
    double best_value = tol;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!passive[i] && gradient[i] > best_value) {
        best_value = gradient[i];
        best = i;
      }
    }
    if (best < 0) break;
    passive[best] = 1;
  }
  return x;
}

// min over (c, kd) >= 0 of [c kd] A [c kd]^T - 2 [c kd] . b, A = [[uu, ud], [ud, dd]] positive
// semi-definite: the unconstrained minimum if it is feasible, else the better edge. Returns the
// objective.
double NonNegative2(double uu, double ud, double dd, double uy, double dy, double* c, double* kd) {
  auto objective = [&](double x, double y) {
    return x * x * uu + 2 * x * y * ud + y * y * dd - 2 * (x * uy + y * dy);
  };
  const double det = uu * dd - ud * ud;
  if (det > 1e-14 * uu * dd && uu > 0 && dd > 0) {
    const double x = (dd * uy - ud * dy) / det, y = (uu * dy - ud * uy) / det;
    if (x >= 0 && y >= 0) {
      *c = x;
      *kd = y;
      return objective(x, y);
    }
  }
  const double x = uu > 0 ? std::max(0.0, uy / uu) : 0.0, y = dd > 0 ? std::max(0.0, dy / dd) : 0.0;
  const double only_c = objective(x, 0), only_kd = objective(0, y);
  *c = only_c <= only_kd ? x : 0.0;
  *kd = only_c <= only_kd ? 0.0 : y;
  return std::min(only_c, only_kd);
}

// The best F0 in [f0_lo, f0_hi] and c, kd >= 0 for a fixed table (parameters q): per channel the
// two-column problem [F0 N q + R q, D] in closed form, F0 by a scan and golden-section search.
// Returns the data chi2.
double SolveDBrdfColours(const Grams& g, const Eigen::VectorXd& q, double f0_lo, double f0_hi,
                         Solution* s) {
  std::array<std::array<double, 10>, 3> m;  // aa ab bb ad bd ay by dd dy yy
  for (int ch = 0; ch < 3; ++ch) {
    m[ch] = {q.dot(g.nn[ch] * q),
             q.dot(g.nr[ch] * q),
             q.dot(g.rr[ch] * q),
             g.nd[ch].dot(q),
             g.rd[ch].dot(q),
             g.ny[ch].dot(q),
             g.ry[ch].dot(q),
             g.dd[ch],
             g.dy[ch],
             g.yy[ch]};
  }
  auto at = [&](double f0, Solution* out) {
    double chi2 = 0;
    for (int ch = 0; ch < 3; ++ch) {
      const auto& v = m[ch];
      const double uu = f0 * f0 * v[0] + 2 * f0 * v[1] + v[2], ud = f0 * v[3] + v[4];
      const double uy = f0 * v[5] + v[6];
      double c = 0, kd = 0;
      chi2 += v[9] + NonNegative2(uu, ud, v[7], uy, v[8], &c, &kd);
      if (out) {
        out->c[ch] = c;
        out->kd[ch] = kd;
      }
    }
    return chi2;
  };
  // F0 on a square-root scale: small values, where the Fresnel rise matters most, get more scan
  // points.
  double f0 = f0_lo;
  if (f0_hi > f0_lo) {
    const auto f0_of = [&](double u) { return f0_lo + (f0_hi - f0_lo) * u * u; };
    f0 = f0_of(MinimizeScalar([&](double u) { return at(f0_of(u), nullptr); }, 0.0, 1.0, 24, 40));
  }
  s->f0 = f0;
  return std::max(0.0, at(f0, s));
}

// The best table parameters q >= 0 and kd >= 0 for fixed F0 and c, with the smoothness penalty's
// Gram matrix (zero: none): one non-negative quadratic in (q, kd), warm-started from s.
void SolveShape(const Grams& g, const Eigen::MatrixXd& penalty_gram, Solution* s) {
  const Eigen::Index np = s->q.size();
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(np + 3, np + 3);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(np + 3);
  const double f0 = s->f0;
  for (int ch = 0; ch < 3; ++ch) {
    const double c = s->c[ch];
    h.topLeftCorner(np, np) +=
        (c * c) * (f0 * f0 * g.nn[ch] + f0 * (g.nr[ch] + g.nr[ch].transpose()) + g.rr[ch]);
    rhs.head(np) += c * (f0 * g.ny[ch] + g.ry[ch]);
    h.block(0, np + ch, np, 1) = c * (f0 * g.nd[ch] + g.rd[ch]);
    h.block(np + ch, 0, 1, np) = h.block(0, np + ch, np, 1).transpose();
    h(np + ch, np + ch) = g.dd[ch];
    rhs[np + ch] = g.dy[ch];
  }
  if (penalty_gram.size() > 0) h.topLeftCorner(np, np) += penalty_gram;
  Eigen::VectorXd x(np + 3);
  x.head(np) = s->q;
  for (int ch = 0; ch < 3; ++ch) x[np + ch] = s->kd[ch];
  if (s->c.Max() <= 0) x.head(np).setZero();
  x = NonNegativeQuadratic(h, rhs, x);
  if (s->c.Max() > 0) s->q = x.head(np);
  for (int ch = 0; ch < 3; ++ch) s->kd[ch] = x[np + ch];
}

// Ceres's parameter blocks (q, F0, c, kd) for the polish and the covariance.
struct CeresBlocks {
  Eigen::VectorXd q;
  double f0 = 0;
  double c[3] = {0, 0, 0}, kd[3] = {0, 0, 0};

  explicit CeresBlocks(const Solution& s) : q(s.q), f0(s.f0) {
    for (int ch = 0; ch < 3; ++ch) {
      c[ch] = s.c[ch];
      kd[ch] = s.kd[ch];
    }
  }
  Solution ToSolution() const {
    Solution s;
    s.q = q;
    s.f0 = f0;
    s.c = {c[0], c[1], c[2]};
    s.kd = {kd[0], kd[1], kd[2]};
    return s;
  }
};

std::unique_ptr<ceres::Problem> MakeCeresProblem(const Problem& p, double f0_lo, double f0_hi,
                                                 CeresBlocks* b) {
  auto problem = std::make_unique<ceres::Problem>();
  problem->AddResidualBlock(new DBrdfCost(p), nullptr, b->q.data(), &b->f0, b->c, b->kd);
  for (Eigen::Index i = 0; i < b->q.size(); ++i)
    problem->SetParameterLowerBound(b->q.data(), i, 0.0);
  if (f0_lo == f0_hi) {
    problem->SetParameterBlockConstant(&b->f0);
  } else {
    problem->SetParameterLowerBound(&b->f0, 0, f0_lo);
    problem->SetParameterUpperBound(&b->f0, 0, f0_hi);
  }
  for (int ch = 0; ch < 3; ++ch) {
    problem->SetParameterLowerBound(b->c, ch, 0.0);
    problem->SetParameterLowerBound(b->kd, ch, 0.0);
  }
  return problem;
}

struct RefineReport {
  int sweeps = 0, ceres_iterations = 0;
  std::string termination;
};

// Step 4's solver (dbrdf_fit.h) from *s, with p.penalty: alternating exact minimization over
// (p, kd) and (F0, c, kd), each a non-negative quadratic solved exactly, the gauge normalized
// after each sweep; then, if max_iterations > 0, a Ceres polish of all parameters together, kept
// if it lowers the objective. Returns the data chi2.
double Refine(const Problem& p, const Grams& grams, double f0_lo, double f0_hi, int max_sweeps,
              int max_iterations, Solution* s, RefineReport* report) {
  report->ceres_iterations = 0;
  const Eigen::MatrixXd penalty_gram =
      p.penalty.rows() > 0 ? Eigen::MatrixXd(p.penalty.transpose() * p.penalty) : Eigen::MatrixXd();
  auto objective = [&](const Solution& x) {
    return Chi2(p, x) + (p.penalty.rows() > 0 ? (p.penalty * x.q).squaredNorm() : 0.0);
  };
  s->f0 = std::clamp(s->f0, f0_lo, f0_hi);
  double previous = objective(*s);
  int quiet = 0;
  report->termination = "alternating solver: sweep limit";
  for (report->sweeps = 0; report->sweeps < max_sweeps;) {
    ++report->sweeps;
    SolveShape(grams, penalty_gram, s);
    SolveDBrdfColours(grams, s->q, f0_lo, f0_hi, s);
    const double scale = p.norm.dot(s->q);
    if (scale > 0) {
      s->q /= scale;
      s->c = s->c * scale;
    }
    const double value = objective(*s);
    quiet = std::abs(previous - value) <= 1e-11 * std::max(value, 1e-300) ? quiet + 1 : 0;
    previous = value;
    if (quiet >= 2) {
      report->termination = "alternating solver converged";
      break;
    }
  }
  if (max_iterations <= 0) return Chi2(p, *s);
  CeresBlocks blocks(*s);
  const auto problem = MakeCeresProblem(p, f0_lo, f0_hi, &blocks);
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = max_iterations;
  solver.function_tolerance = 1e-10;
  solver.gradient_tolerance = 1e-12;
  solver.parameter_tolerance = 1e-10;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, problem.get(), &summary);
  report->ceres_iterations = static_cast<int>(summary.iterations.size());
  const Solution polished = blocks.ToSolution();
  if (objective(polished) < objective(*s)) *s = polished;
  report->termination += "; Ceres polish: " + summary.message;
  return Chi2(p, *s);
}

// The band-limited retro-reflection slice f^(w, w) / cos(theta) at direction w, per channel.
Rgb RetroSlice(const ZonalTensor& data, const ZonalBasis& zb, const Vec3& w) {
  std::vector<double> z(zb.size());
  zb.Eval(w, z.data());
  const Eigen::Map<const Eigen::VectorXd> zv(z.data(), zb.size());
  Rgb r;
  for (int ch = 0; ch < 3; ++ch) r[ch] = zv.dot(data.z[ch] * zv) / w.z;
  return r;
}

}  // namespace

nlohmann::json DBrdfFitResult::ToJson() const {
  auto rgb = [](const Rgb& c) { return nlohmann::json::array({c.r, c.g, c.b}); };
  auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  nlohmann::json j;
  j["c"] = rgb(params.c);
  j["F0"] = params.f0;
  j["kd"] = rgb(params.kd);
  j["theta_samples"] = params.p_h.theta_samples;
  j["phi_samples"] = params.p_h.phi_samples;
  j["table"] = isotropic_table ? "1-D p(theta_h) (isotropic data)" : "2-D p(theta_h, phi_h) (anisotropic data)";
  j["alpha_equivalent"] = alpha_equivalent;
  j["tail_alpha"] = tail_alpha;
  j["knots"] = knots;
  j["smoothness_weight"] = smoothness_weight;
  j["initial"] = initial;
  nlohmann::json u;
  u["available"] = uncertainty.available;
  u["F0"] = finite(uncertainty.f0);
  u["c"] = {finite(uncertainty.c.r), finite(uncertainty.c.g), finite(uncertainty.c.b)};
  u["kd"] = {finite(uncertainty.kd.r), finite(uncertainty.kd.g), finite(uncertainty.kd.b)};
  j["uncertainty"] = u;
  j["isotropy"] = {{"isotropic", isotropy.isotropic},
                   {"anisotropic_energy_fraction", isotropy.anisotropic_energy_fraction},
                   {"chi2_per_dof", isotropy.chi2_per_dof}};
  return j;
}

void DBrdfFitOptions::Validate() const {
  OptionChecker check("DBrdfFitOptions");
  // p(h)'s table nodes fall on whole degrees: theta_samples - 1 divides 90.
  const auto divides_90 = [](int samples) { return samples >= 3 && 90 % (samples - 1) == 0; };
  check
      .Require(divides_90(theta_samples), "theta_samples",
               "must be 1 + a divisor of 90 (e.g. 91, 46, 31; got " +
                   std::to_string(theta_samples) + ")")
      .Require(divides_90(anisotropic_theta_samples), "anisotropic_theta_samples",
               "must be 1 + a divisor of 90 (e.g. 46, 31; got " +
                   std::to_string(anisotropic_theta_samples) + ")")
      .AtLeast("anisotropic_phi_samples", anisotropic_phi_samples, 2)
      .AtLeast("max_sweeps", max_sweeps, 1)
      .AtLeast("max_iterations", max_iterations, 1)
      .Require(f0_min >= 0 && f0_min <= f0_max && f0_max <= 1, "f0_min, f0_max",
               "must satisfy 0 <= f0_min <= f0_max <= 1 (--f0-range; got " +
                   FormatOptionValue(f0_min) + ", " + FormatOptionValue(f0_max) + ")")
      .Require(smoothness >= 0 && std::isfinite(smoothness), "smoothness",
               "must be >= 0 and finite (got " + FormatOptionValue(smoothness) + ")")
      .Nested("quadrature", quadrature)
      .ThrowIfInvalid();
}

DBrdfFitter::DBrdfFitter(const Zone& zone, int order, const DBrdfFitOptions& options)
    : zone_(zone), order_(order), options_(options) {
  const auto t0 = WallClock::now();
  options.Validate();
  PairQuadratureOptions q = options.quadrature;
  q.theta_h_cells = 90;
  if (q.theta_nodes == 0) q.theta_nodes = DefaultThetaNodes(zone, order);
  quadrature_ = std::make_unique<PairQuadrature>(zone, order, q);
  if (options.table != DBrdfFitOptions::Table::kAnisotropic) {
    isotropic_ = std::make_unique<DBrdfProjection>(ProjectDBrdfTable(*quadrature_, options.theta_samples, 1));
  }
  precompute_seconds_ = SecondsSince(t0);
}

DBrdfFitter::~DBrdfFitter() = default;

const DBrdfProjection& DBrdfFitter::Projection(bool isotropic) const {
  std::lock_guard<std::mutex> lock(ProjectionMutex());
  auto& slot = isotropic ? isotropic_ : anisotropic_;
  if (!slot) {
    const auto t0 = WallClock::now();
    slot = std::make_unique<DBrdfProjection>(
        isotropic ? ProjectDBrdfTable(*quadrature_, options_.theta_samples, 1)
                  : ProjectDBrdfTable(*quadrature_, options_.anisotropic_theta_samples,
                                      options_.anisotropic_phi_samples));
    precompute_seconds_ += SecondsSince(t0);
  }
  return *slot;
}

DBrdfFitResult DBrdfFitter::Fit(const ZonalTensor& data) const {
  const auto t_start = WallClock::now();
  if (data.order != order_ || !(data.zone() == zone_)) {
    throw InputError("D-BRDF fit: the data (zone " + data.zone().ToString() + ", order " +
                     std::to_string(data.order) + ") do not match the fitter's (zone " +
                     zone_.ToString() + ", order " + std::to_string(order_) + ")");
  }
  const int n = data.size();
  for (int ch = 0; ch < 3; ++ch) {
    if (data.z[ch].rows() != n || data.z[ch].cols() != n || data.variance[ch].rows() != n ||
        data.variance[ch].cols() != n) {
      throw InputError("D-BRDF fit: the data's tensors are not " + std::to_string(n) + " x " +
                       std::to_string(n));
    }
  }
  DBrdfFitResult result;
  result.isotropy = AnalyzeIsotropy(data);
  bool isotropic = result.isotropy.isotropic;
  if (options_.table == DBrdfFitOptions::Table::kIsotropic) isotropic = true;
  if (options_.table == DBrdfFitOptions::Table::kAnisotropic) isotropic = false;
  result.isotropic_table = isotropic;
  const int theta_samples = isotropic ? options_.theta_samples : options_.anisotropic_theta_samples;
  const int phi_samples = isotropic ? 1 : options_.anisotropic_phi_samples;
  const double table_step = 0.5 * M_PI / (theta_samples - 1);

  // The data in the layout of the projection.
  std::array<Eigen::VectorXd, 3> y, variance;
  if (isotropic) {
    const IsotropicData iso = IsotropicCoefficients(data);
    y = iso.z;
    variance = iso.variance;
  } else {
    for (int ch = 0; ch < 3; ++ch) {
      y[ch].resize(static_cast<Eigen::Index>(n) * n);
      variance[ch].resize(static_cast<Eigen::Index>(n) * n);
      for (int k = 0; k < n; ++k) {
        for (int j = 0; j < n; ++j) {
          y[ch][static_cast<Eigen::Index>(k) * n + j] = data.z[ch](k, j);
          variance[ch][static_cast<Eigen::Index>(k) * n + j] = data.variance[ch](k, j);
        }
      }
    }
  }
  Problem problem;
  problem.w = MakeFitWeights(y, variance);
  result.conditions = problem.w.conditions;
  // A black model with a GGX-shaped p: what degenerate data give.
  auto black = [&](double alpha) {
    std::vector<double> p(static_cast<size_t>(theta_samples) * phi_samples);
    for (int j = 0; j < theta_samples; ++j) {
      for (int k = 0; k < phi_samples; ++k) p[j * phi_samples + k] = GgxD(alpha, j * table_step);
    }
    DBrdfParams params;
    params.p_h.theta_samples = theta_samples;
    params.p_h.phi_samples = phi_samples;
    params.p_h.p = std::move(p);
    params.p_h.Normalize();
    params.c = Rgb(0.0);
    params.f0 = 0.04;
    params.kd = Rgb(0.0);
    return params;
  };
  if (!problem.w.any_signal) {
    result.params = black(0.3);
    result.tail_alpha = 0.3;
    result.total_seconds = SecondsSince(t_start);
    return result;
  }
  const DBrdfProjection& projection = Projection(isotropic);
  const auto t_solve = WallClock::now();
  const Eigen::VectorXd norm_table = NormalizationWeights(theta_samples, phi_samples);

  // 2. GGX scan: p = D_alpha at every node (the same for every phi), normalized.
  auto ggx_table = [&](double alpha) {
    Eigen::VectorXd p(theta_samples * phi_samples);
    for (int j = 0; j < theta_samples; ++j) p.segment(j * phi_samples, phi_samples).setConstant(GgxD(alpha, j * table_step));
    return Eigen::VectorXd(p / norm_table.dot(p));
  };
  Solution linear;
  auto scan = [&](double log_alpha) {
    const Eigen::VectorXd p = ggx_table(std::exp(log_alpha));
    Solution s;
    return SolveLinear(problem.w, projection.normal * p, projection.grazing * p, projection.diffuse, &s);
  };
  const double log_alpha = MinimizeScalar(scan, std::log(0.01), std::log(1.5), 28, 30);
  result.tail_alpha = std::exp(log_alpha);
  const Eigen::VectorXd p_ggx = ggx_table(result.tail_alpha);
  SolveLinear(problem.w, projection.normal * p_ggx, projection.grazing * p_ggx, projection.diffuse, &linear);

  // 3. Retro-reflection extraction inside the zone, blended with the GGX lobe outside.
  const ZonalBasis zb(data.zone(), data.order);
  const double theta_min = data.theta_min_rad, theta_max = data.theta_max_rad;
  const double blend = 5.0 * M_PI / 180.0;
  Eigen::VectorXd p_init = p_ggx;
  const double a1_sum2 = linear.c.r * linear.c.r + linear.c.g * linear.c.g + linear.c.b * linear.c.b;
  if (a1_sum2 > 0 && linear.f0 > 0) {
    for (int j = 0; j < theta_samples; ++j) {
      const double theta = j * table_step;
      if (theta < theta_min || theta > theta_max) continue;
      const double ramp = std::min({1.0, (theta - theta_min) / blend, (theta_max - theta) / blend});
      for (int k = 0; k < phi_samples; ++k) {
        const Vec3 w = SphericalDirection(theta, k * 2.0 * M_PI / phi_samples);
        const Rgb r = RetroSlice(data, zb, w);
        const double geometry = 2.0 * w.z - w.z * w.z;
        double num = 0;
        for (int ch = 0; ch < 3; ++ch) {
          const double a1 = linear.c[ch] * linear.f0;
          num += a1 * (r[ch] - linear.kd[ch] / M_PI) * geometry;
        }
        const double p_retro = std::max(0.0, num / (a1_sum2 * linear.f0 * linear.f0));
        const int row = j * phi_samples + k;
        p_init[row] = ramp * p_retro + (1.0 - ramp) * p_ggx[row];
      }
    }
  }

  // 4. Knots and the map to the table.
  const int last_node = std::min(theta_samples - 1, static_cast<int>(std::ceil(theta_max / table_step - 1e-9)));
  const std::vector<int> knots = KnotNodes(theta_samples, last_node);
  const Eigen::MatrixXd map = TableMap(theta_samples, phi_samples, knots, result.tail_alpha);
  result.knots = static_cast<int>(map.cols());
  problem.nq = projection.normal * map;
  problem.rq = projection.grazing * map;
  problem.diffuse = projection.diffuse;  // kd in albedo units
  problem.norm = norm_table.transpose() * map;
  // The normalization holds the c-p gauge in the Ceres polish and the covariance: stiff, so that
  // it acts as a constraint (and the covariance of c is that of the data, not of the gauge). The
  // alternating solver holds it exactly.
  problem.norm_weight = 1e4 * std::sqrt(static_cast<double>(problem.w.used));
  const Grams grams = MakeGrams(problem);

  // Knot values from a table: least squares through the map (exact at the knots).
  auto knots_of = [&](const Eigen::VectorXd& table) {
    Eigen::VectorXd q = map.colPivHouseholderQr().solve(table);
    return Eigen::VectorXd(q.cwiseMax(0.0));
  };
  Solution from_retro = linear, from_ggx = linear;
  from_retro.q = knots_of(p_init);
  from_ggx.q = knots_of(p_ggx);
  const bool retro_better = Chi2(problem, from_retro) < Chi2(problem, from_ggx);
  Solution s = retro_better ? from_retro : from_ggx;
  result.initial = retro_better ? "retro+ggx" : "ggx";
  // Scale q so that p is normalized (the gauge), c compensating.
  const double scale = problem.norm.dot(s.q);
  if (scale > 0) {
    s.q /= scale;
    s.c = s.c * scale;
  }
  const double f0_lo = options_.f0_min, f0_hi = options_.f0_max;
  RefineReport refine_report;
  int iterations = 0;
  auto refine = [&](Solution* x, bool polish) {
    const double chi2 = Refine(problem, grams, f0_lo, f0_hi, options_.max_sweeps,
                               polish ? options_.max_iterations : 0, x, &refine_report);
    iterations += refine_report.sweeps + refine_report.ceres_iterations;
    return chi2;
  };
  const double chi2_free = refine(&s, false);

  // 5. A misfit beyond the noise (chi2 more than 3 standard deviations above dof): the smoothness
  // prior, in proportion to the misfit, accepted only while it costs at most kPriorCost of it:
  // where the misfit is the model's own (a mirror at low order, chi2/dof 1e6) the data outweigh
  // any smoothness, so the weight is lowered tenfold up to twice, else the prior is dropped.
  const int dof = std::max(1, problem.w.used - static_cast<int>(s.q.size()) - 7);
  const Eigen::MatrixXd curvature =
      RatioCurvature(theta_samples, phi_samples, knots, result.tail_alpha);
  if (options_.smoothness > 0 && curvature.rows() > 0 &&
      chi2_free > dof + 3.0 * std::sqrt(2.0 * dof)) {
    constexpr double kPriorCost = 0.1;
    const double unit = std::sqrt((chi2_free - dof) / curvature.rows());
    const Solution free_fit = s;
    for (double lambda = options_.smoothness; lambda >= 0.01 * options_.smoothness * 0.999;
         lambda *= 0.1) {
      Solution trial = free_fit;
      problem.penalty = (lambda * unit) * curvature;
      if (refine(&trial, false) <= (1.0 + kPriorCost) * chi2_free) {
        s = trial;
        result.smoothness_weight = lambda * unit;
        break;
      }
    }
    if (result.smoothness_weight == 0) problem.penalty.resize(0, 0);
  }
  // The Ceres polish of the solution (with its prior).
  refine(&s, true);

  const auto prediction = Predict(problem, s);
  result.statistics = ComputeFitStatistics(problem.w, prediction, static_cast<int>(s.q.size()) + 7);
  result.statistics.iterations = iterations;
  result.statistics.termination = refine_report.termination;
  const Solution& fitted = s;

  // Uncertainties: ceres::Covariance at the solution (with the prior when it was applied).
  if (options_.covariance) {
    CeresBlocks blocks(s);
    const auto ceres_problem = MakeCeresProblem(problem, f0_lo, f0_hi, &blocks);
    const auto sd = ParameterStandardDeviations(*ceres_problem,
                                                {{&blocks.f0, 1}, {blocks.c, 3}, {blocks.kd, 3}},
                                                result.statistics.chi2_per_dof);
    if (sd) {
      result.uncertainty.available = true;
      result.uncertainty.f0 = (*sd)[0][0];
      for (int ch = 0; ch < 3; ++ch) {
        result.uncertainty.c[ch] = (*sd)[1][ch];
        result.uncertainty.kd[ch] = (*sd)[2][ch];
      }
    } else {
      result.conditions.push_back(kUncertaintiesUnavailable);
    }
  }

  // The table, normalized, the scale folded into c.
  Eigen::VectorXd table = (map * fitted.q).cwiseMax(0.0);
  double integral = norm_table.dot(table);
  DBrdfParams params;
  params.p_h.theta_samples = theta_samples;
  params.p_h.phi_samples = phi_samples;
  const bool specular = integral > 0 && (fitted.c.r + fitted.c.g + fitted.c.b) > 0;
  if (specular) {
    params.p_h.p.assign(table.data(), table.data() + table.size());
    params.p_h.Normalize();
    params.c = fitted.c * integral;
  } else {
    const DBrdfParams b = black(result.tail_alpha);
    params.p_h = b.p_h;
    params.c = Rgb(0.0);
    result.conditions.push_back("no specular reflection detected: c = 0 and p(h) is the GGX prior "
                                "(alpha " + std::to_string(result.tail_alpha) + ")");
  }
  params.f0 = std::clamp(fitted.f0, 0.0, 1.0);
  params.kd = {std::max(0.0, fitted.kd.r), std::max(0.0, fitted.kd.g), std::max(0.0, fitted.kd.b)};
  result.params = params;
  result.fitted = true;

  // Alpha-equivalent: the GGX whose retro-reflection has the shape of the fitted model's. At
  // retro-reflection the D-BRDF is c F0 p(theta) / (2 cos - cos^2) (thesis eq. 2.15) and GGX is
  // F0 D(theta) G2 / (4 cos^2), so a GGX lobe corresponds to p proportional to
  // R_alpha(theta) = D(theta) G2(theta) (2 - cos theta) / (4 cos theta). alpha minimizes
  // sum w (p - s R_alpha)^2 over the table nodes up to theta_max, the scale s solved in closed
  // form, w = sin cos (the projected measure) + 1e-3.
  {
    std::vector<double> thetas, ps, ws;
    for (int j = 0; j <= last_node; ++j) {
      const double theta = j * table_step;
      double mean = 0;
      for (int k = 0; k < phi_samples; ++k) mean += params.p_h.At(j, k);
      thetas.push_back(theta);
      ps.push_back(mean / phi_samples);
      ws.push_back(std::sin(theta) * std::cos(theta) + 1e-3);
    }
    auto retro = [](double alpha, double theta) {
      const double c = std::cos(theta), t = std::tan(theta);
      const double lambda = 0.5 * (std::sqrt(1.0 + alpha * alpha * t * t) - 1.0);
      return GgxD(alpha, theta) / (1.0 + 2.0 * lambda) * (2.0 - c) / (4.0 * c);
    };
    auto misfit = [&](double log_alpha) {
      const double alpha = std::exp(log_alpha);
      double pr = 0, rr = 0;
      for (size_t i = 0; i < thetas.size(); ++i) {
        const double r = retro(alpha, thetas[i]);
        pr += ws[i] * ps[i] * r;
        rr += ws[i] * r * r;
      }
      const double scale = rr > 0 ? pr / rr : 0.0;
      double e = 0;
      for (size_t i = 0; i < thetas.size(); ++i) {
        const double d = ps[i] - scale * retro(alpha, thetas[i]);
        e += ws[i] * d * d;
      }
      return e;
    };
    result.alpha_equivalent = std::exp(MinimizeScalar(misfit, std::log(0.005), std::log(2.0), 40, 40));
  }
  if (specular && result.alpha_equivalent < 1.5 * table_step) {
    char text[200];
    std::snprintf(text, sizeof(text),
                  "the lobe (alpha-equivalent %.3f) is as narrow as the table's %.1f deg steps or "
                  "narrower: p(h) holds it at the table's resolution (mirror-like sample)",
                  result.alpha_equivalent, table_step * 180 / M_PI);
    result.conditions.push_back(text);
  }
  if (result.statistics.chi2_per_dof > 25) {
    char text[200];
    std::snprintf(text, sizeof(text),
                  "the D-BRDF does not explain the data within their noise (chi2/dof = %.3g, "
                  "relative residual %.2g%%)",
                  result.statistics.chi2_per_dof, 100 * result.statistics.relative_residual);
    result.conditions.push_back(text);
  }
  result.solve_seconds = SecondsSince(t_solve);
  result.precompute_seconds = precompute_seconds_;
  result.total_seconds = SecondsSince(t_start);
  return result;
}

DBrdfFitResult FitDBrdf(const ZonalTensor& data, const DBrdfFitOptions& options) {
  if (const std::string problems = data.Problems(); !problems.empty() &&
      problems.find("not finite") == std::string::npos && problems.find("NaN") == std::string::npos) {
    throw InputError("D-BRDF fit: " + problems);
  }
  const auto t0 = WallClock::now();
  DBrdfFitter fitter(data.zone(), data.order, options);
  DBrdfFitResult result = fitter.Fit(data);
  result.total_seconds = SecondsSince(t0);
  return result;
}

}  // namespace zbrdf
