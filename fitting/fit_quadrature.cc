#include "fitting/fit_quadrature.h"

#include <algorithm>
#include <cmath>
#include <complex>

#include "basis/error.h"
#include "basis/legendre.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "basis/spherical_harmonics.h"
#include "brdf/fresnel.h"

namespace zbrdf {
namespace {

struct PairGeometry {
  double ci, si, cr, sr;
};

// Half-vector angle and the azimuth gamma of h relative to w_r, at azimuth difference delta.
void HalfVectorAt(const PairGeometry& g, double delta, double* theta_h, double* gamma,
                  double* k_dot_h) {
  const double cd = std::cos(delta), sd = std::sin(delta);
  const double hx = g.si * cd + g.sr, hy = g.si * sd, hz = g.ci + g.cr;
  const double length2 = hx * hx + hy * hy + hz * hz;  // |w_i + w_r|^2
  *theta_h = std::atan2(std::sqrt(hx * hx + hy * hy), hz);
  if (gamma) *gamma = std::atan2(hy, hx);
  if (k_dot_h) *k_dot_h = 0.5 * std::sqrt(length2);
}

// Delta at which theta_h equals a given value (see the header).
double DeltaAtThetaH(const PairGeometry& g, double theta_h) {
  const double c = std::cos(theta_h);
  const double sum = g.ci + g.cr;
  const double cos_delta =
      ((sum * sum) / (c * c) - 2.0 - 2.0 * g.ci * g.cr) / (2.0 * g.si * g.sr);
  return std::acos(std::clamp(cos_delta, -1.0, 1.0));
}

}  // namespace

void PairQuadratureOptions::Validate() const {
  OptionChecker check("PairQuadratureOptions");
  check.InRange("theta_nodes", theta_nodes, 0, 512)
      .InRange("theta_h_cells", theta_h_cells, 1, 3600)
      .InRange("gauss_nodes", gauss_nodes, 1, 64)
      .ThrowIfInvalid();
}

PairQuadrature::PairQuadrature(const Zone& zone, int order, const PairQuadratureOptions& options)
    : zone_(zone), order_(order) {
  if (order < 0 || order > 30) {
    throw InputError("fit quadrature: order " + std::to_string(order) + " is out of range [0, 30]");
  }
  options.Validate();
  n_ = options.theta_nodes > 0 ? options.theta_nodes : 2 * order + 32;
  cells_ = options.theta_h_cells;
  rule_ = CosThetaPsiRule(zone, n_);
  const ZonalBasis zb(zone, order);
  part_size_ = LegendreCount(order);
  theta_part_.resize(static_cast<size_t>(n_) * part_size_);
  for (int t = 0; t < n_; ++t) zb.EvalThetaPart(rule_.x[t], &theta_part_[static_cast<size_t>(t) * part_size_]);

  const GaussLegendreRule gauss = GaussLegendre(options.gauss_nodes);
  const double step = theta_h_step();
  const double harmonic = std::max(1, order);
  // Per pair, built in parallel into separate lists, then concatenated in pair order.
  struct PairNodes {
    std::vector<Node> nodes;
    std::vector<std::pair<int, int>> runs;  // (cell, node count)
  };
  std::vector<PairNodes> per_pair(static_cast<size_t>(n_) * n_);
  ParallelFor(static_cast<int64_t>(n_) * n_, 16, [&](int64_t p0, int64_t p1) {
    for (int64_t p = p0; p < p1; ++p) {
      const int ti = static_cast<int>(p / n_), tr = static_cast<int>(p % n_);
      const PairGeometry g{rule_.x[ti], rule_.s_x[ti], rule_.x[tr], rule_.s_x[tr]};
      const double theta_i = std::atan2(g.si, g.ci), theta_r = std::atan2(g.sr, g.cr);
      const double hi = 0.5 * (theta_i + theta_r), lo = 0.5 * std::abs(theta_i - theta_r);
      // Breakpoints in Delta, ascending (theta_h descending).
      std::vector<double> breaks{0.0};
      for (int k = static_cast<int>(std::floor(hi / step)); k * step > lo; --k) {
        if (k * step >= hi) continue;
        const double d = DeltaAtThetaH(g, k * step);
        if (d > breaks.back()) breaks.push_back(d);
      }
      if (breaks.back() < M_PI) breaks.push_back(M_PI);
      PairNodes& out = per_pair[p];
      // Recursive split of [a, b] until the azimuthal harmonics are resolved.
      std::vector<std::pair<double, double>> pieces;
      for (size_t b = 0; b + 1 < breaks.size(); ++b) {
        const double a0 = breaks[b], b0 = breaks[b + 1];
        if (!(b0 > a0)) continue;
        double mid_theta_h;
        HalfVectorAt(g, 0.5 * (a0 + b0), &mid_theta_h, nullptr, nullptr);
        const int cell = std::clamp(static_cast<int>(mid_theta_h / step), 0, cells_ - 1);
        pieces.clear();
        std::vector<std::pair<double, double>> stack{{a0, b0}};
        while (!stack.empty()) {
          const auto [a, bb] = stack.back();
          stack.pop_back();
          double th, ga, gb;
          HalfVectorAt(g, a, &th, &ga, nullptr);
          HalfVectorAt(g, bb, &th, &gb, nullptr);
          const bool fine = (bb - a) * harmonic <= 1.0 && std::abs(gb - ga) * 2 * harmonic <= 1.0;
          if (fine || bb - a < 1e-9) {
            pieces.push_back({a, bb});
          } else {
            const double m = 0.5 * (a + bb);
            stack.push_back({m, bb});
            stack.push_back({a, m});
          }
        }
        int count = 0;
        for (const auto& [a, bb] : pieces) {
          const double half = 0.5 * (bb - a);
          for (size_t q = 0; q < gauss.nodes.size(); ++q) {
            Node node;
            node.delta = a + half * (1.0 + gauss.nodes[q]);
            node.weight = 2.0 * half * gauss.weights[q];
            HalfVectorAt(g, node.delta, &node.theta_h, nullptr, &node.k_dot_h);
            node.cos_delta = std::cos(node.delta);
            node.sin_delta = std::sin(node.delta);
            out.nodes.push_back(node);
            ++count;
          }
        }
        out.runs.push_back({cell, count});
      }
    }
  });
  int64_t total = 0;
  for (const PairNodes& p : per_pair) total += static_cast<int64_t>(p.nodes.size());
  nodes_.reserve(total);
  pair_segments_.assign(static_cast<size_t>(n_) * n_ + 1, 0);
  cell_segments_.assign(cells_, {});
  for (size_t p = 0; p < per_pair.size(); ++p) {
    pair_segments_[p] = static_cast<int>(segments_.size());
    int64_t begin = static_cast<int64_t>(nodes_.size());
    for (const auto& [cell, count] : per_pair[p].runs) {
      cell_segments_[cell].push_back(static_cast<int>(segments_.size()));
      segments_.push_back({static_cast<int>(p), cell, begin, begin + count});
      begin += count;
    }
    nodes_.insert(nodes_.end(), per_pair[p].nodes.begin(), per_pair[p].nodes.end());
    std::vector<Node>().swap(per_pair[p].nodes);
  }
  pair_segments_.back() = static_cast<int>(segments_.size());
}

void PairQuadrature::Directions(int pair, const Node& node, Vec3* w_i, Vec3* w_r) const {
  const int ti = pair / n_, tr = pair % n_;
  *w_r = {rule_.s_x[tr], 0.0, rule_.x[tr]};
  *w_i = {rule_.s_x[ti] * node.cos_delta, rule_.s_x[ti] * node.sin_delta, rule_.x[ti]};
}

namespace {

// G_m = 2 pi Theta_m^T W H_m W Theta_m for every m; h[m] is n x n (row ti, column tr).
Eigen::VectorXd ContractIsotropic(const PairQuadrature& q, const std::vector<Eigen::MatrixXd>& h) {
  const int order = q.order(), n = q.theta_nodes();
  const IsotropicLayout layout(order);
  Eigen::VectorXd out(layout.size());
  for (int m = 0; m <= order; ++m) {
    const int width = order + 1 - m;
    Eigen::MatrixXd theta(n, width);
    for (int t = 0; t < n; ++t) {
      for (int l = m; l <= order; ++l) {
        theta(t, l - m) = q.theta_rule().weight[t] * q.ThetaPart(t)[LegendreIndex(l, m)];
      }
    }
    const Eigen::MatrixXd g = 2.0 * M_PI * (theta.transpose() * h[m] * theta);
    for (int l = 0; l < width; ++l) {
      for (int lp = 0; lp < width; ++lp) out[layout.Index(m, l + m, lp + m)] = g(l, lp);
    }
  }
  return out;
}

}  // namespace

Eigen::VectorXd PairQuadrature::ProjectIsotropic(std::span<const double> g) const {
  const std::span<const double> one[1] = {g};
  return std::move(ProjectIsotropicAll(one)[0]);
}

std::vector<Eigen::VectorXd> PairQuadrature::ProjectIsotropicAll(
    std::span<const std::span<const double>> g) const {
  for (const auto& v : g) {
    ZBRDF_ASSERT(static_cast<int64_t>(v.size()) == size(),
                 "one value per quadrature node expected");
  }
  const size_t count = g.size();
  const int width = order_ + 1;
  std::vector<std::vector<Eigen::MatrixXd>> h(count);
  for (auto& hc : h) hc.assign(width, Eigen::MatrixXd::Zero(n_, n_));
  ParallelFor(static_cast<int64_t>(n_) * n_, 64, [&](int64_t p0, int64_t p1) {
    std::vector<double> cm(width), sum(count * width);
    for (int64_t p = p0; p < p1; ++p) {
      std::fill(sum.begin(), sum.end(), 0.0);
      for (int s = pair_segments_[p]; s < pair_segments_[p + 1]; ++s) {
        for (int64_t i = segments_[s].begin; i < segments_[s].end; ++i) {
          CosMultiplesOfCos(order_, nodes_[i].cos_delta, cm.data());
          for (size_t c = 0; c < count; ++c) {  // each function summed as ProjectIsotropic sums it
            const double w = nodes_[i].weight * g[c][i];
            double* sum_c = &sum[c * width];
            for (int m = 0; m < width; ++m) sum_c[m] += w * cm[m];
          }
        }
      }
      for (size_t c = 0; c < count; ++c) {
        for (int m = 0; m < width; ++m) h[c][m](p / n_, p % n_) = sum[c * width + m];
      }
    }
  });
  std::vector<Eigen::VectorXd> out;
  for (const auto& hc : h) out.push_back(ContractIsotropic(*this, hc));
  return out;
}

std::array<Eigen::VectorXd, 3> PairQuadrature::ProjectIsotropicBrdf(const Brdf& brdf) const {
  std::array<std::vector<double>, 3> g;
  for (auto& v : g) v.resize(nodes_.size());
  ParallelFor(static_cast<int64_t>(n_) * n_, 16, [&](int64_t p0, int64_t p1) {
    std::vector<Vec3> wi, wr;
    std::vector<Rgb> f;
    for (int64_t p = p0; p < p1; ++p) {
      const int64_t begin = segments_[pair_segments_[p]].begin;
      const int64_t end = pair_segments_[p + 1] > pair_segments_[p]
                              ? segments_[pair_segments_[p + 1] - 1].end
                              : begin;
      if (pair_segments_[p + 1] == pair_segments_[p]) continue;
      wi.resize(end - begin);
      wr.resize(end - begin);
      f.resize(end - begin);
      for (int64_t i = begin; i < end; ++i) {
        Directions(static_cast<int>(p), nodes_[i], &wi[i - begin], &wr[i - begin]);
      }
      brdf.EvalBatch(wi, wr, f);
      for (int64_t i = begin; i < end; ++i) {
        const double cos_i = wi[i - begin].z;
        for (int ch = 0; ch < 3; ++ch) g[ch][i] = f[i - begin][ch] * cos_i;
      }
    }
  });
  const std::span<const double> channels[3] = {g[0], g[1], g[2]};
  std::vector<Eigen::VectorXd> z = ProjectIsotropicAll(channels);
  return {std::move(z[0]), std::move(z[1]), std::move(z[2])};
}

namespace {

// The D-BRDF's denominator and Fresnel weight at a node.
struct DBrdfTerms {
  double normal, grazing;  // (1 - W) cos_i / d and W cos_i / d
};
inline DBrdfTerms TermsAt(double ci, double cr, double k_dot_h) {
  const double d = ci + cr - ci * cr;
  const double w = SchlickWeight(k_dot_h);
  return {(1.0 - w) * ci / d, w * ci / d};
}

DBrdfProjection ProjectIsotropicTable(const PairQuadrature& q, int theta_samples) {
  const int order = q.order(), n = q.theta_nodes();
  const int table_cells = theta_samples - 1;
  const int ratio = q.theta_h_cells() / table_cells;
  const double table_step = 0.5 * M_PI / table_cells;
  const IsotropicLayout layout(order);
  // Per table cell: contributions to its lower and upper node, normal and grazing parts.
  std::vector<std::array<Eigen::VectorXd, 4>> per_cell(table_cells);
  const auto& rule = q.theta_rule();
  ParallelFor(table_cells, 1, [&](int64_t c0, int64_t c1) {
    std::vector<double> cm(order + 1);
    for (int64_t cell = c0; cell < c1; ++cell) {
      std::array<std::vector<Eigen::MatrixXd>, 4> h;
      for (auto& v : h) v.assign(order + 1, Eigen::MatrixXd::Zero(n, n));
      bool any = false;
      for (int sub = 0; sub < ratio; ++sub) {
        for (int s : q.cell_segments()[cell * ratio + sub]) {
          const PairQuadrature::Segment& seg = q.segments()[s];
          const int ti = seg.pair / n, tr = seg.pair % n;
          const double ci = rule.x[ti], cr = rule.x[tr];
          for (int64_t i = seg.begin; i < seg.end; ++i) {
            const PairQuadrature::Node& node = q.nodes()[i];
            const double t = std::clamp(node.theta_h / table_step - cell, 0.0, 1.0);
            const DBrdfTerms terms = TermsAt(ci, cr, node.k_dot_h);
            CosMultiplesOfCos(order, node.cos_delta, cm.data());
            const double v[4] = {(1 - t) * terms.normal, t * terms.normal, (1 - t) * terms.grazing,
                                 t * terms.grazing};
            for (int e = 0; e < 4; ++e) {
              const double w = node.weight * v[e];
              for (int m = 0; m <= order; ++m) h[e][m](ti, tr) += w * cm[m];
            }
            any = true;
          }
        }
      }
      for (int e = 0; e < 4; ++e) {
        per_cell[cell][e] = any ? ContractIsotropic(q, h[e]) : Eigen::VectorXd::Zero(layout.size());
      }
    }
  });
  DBrdfProjection out;
  out.isotropic = true;
  out.normal = Eigen::MatrixXd::Zero(layout.size(), theta_samples);
  out.grazing = Eigen::MatrixXd::Zero(layout.size(), theta_samples);
  for (int cell = 0; cell < table_cells; ++cell) {
    out.normal.col(cell) += per_cell[cell][0];
    out.normal.col(cell + 1) += per_cell[cell][1];
    out.grazing.col(cell) += per_cell[cell][2];
    out.grazing.col(cell + 1) += per_cell[cell][3];
  }
  // Diffuse: H_0 = integral_0^2pi cos_i / pi dDelta = 2 cos_i exactly; H_m = 0 for m > 0.
  std::vector<Eigen::MatrixXd> h(order + 1, Eigen::MatrixXd::Zero(n, n));
  for (int ti = 0; ti < n; ++ti) h[0].row(ti).setConstant(2.0 * rule.x[ti]);
  out.diffuse = ContractIsotropic(q, h);
  return out;
}

DBrdfProjection ProjectAnisotropicTable(const PairQuadrature& q, int theta_samples,
                                        int phi_samples) {
  const int order = q.order(), n = q.theta_nodes(), size = ShCount(order);
  const int table_cells = theta_samples - 1;
  const int ratio = q.theta_h_cells() / table_cells;
  const double table_step = 0.5 * M_PI / table_cells;
  const int span = 2 * order + 1;  // s in [-order, order] -> s + order
  // Packed (s, s', l, l') index with l >= |s|, l' >= |s'|.
  std::vector<int> s_offset(span + 1, 0);
  for (int s = -order; s <= order; ++s) {
    s_offset[s + order + 1] = s_offset[s + order] + (order + 1 - std::abs(s));
  }
  const int packed_side = s_offset[span];  // = ShCount(order)
  auto packed = [&](int s, int l, int sp, int lp) {
    return static_cast<size_t>(s_offset[s + order] + (l - std::abs(s))) * packed_side +
           s_offset[sp + order] + (lp - std::abs(sp));
  };
  const auto& rule = q.theta_rule();
  // V[cell][e]: packed (s, l) x (s', l') sums, e: lower/upper node x normal/grazing.
  std::vector<std::array<std::vector<double>, 4>> per_cell(table_cells);
  ParallelFor(table_cells, 1, [&](int64_t c0, int64_t c1) {
    std::vector<std::complex<double>> a(span), b(span);
    std::vector<double> t_pair(4 * span * span);
    std::vector<double> u(4 * static_cast<size_t>(span) * packed_side);
    for (int64_t cell = c0; cell < c1; ++cell) {
      std::vector<int> segs;
      for (int sub = 0; sub < ratio; ++sub) {
        const auto& list = q.cell_segments()[cell * ratio + sub];
        segs.insert(segs.end(), list.begin(), list.end());
      }
      std::sort(segs.begin(), segs.end());  // segment order is pair order
      auto& v = per_cell[cell];
      for (auto& e : v) e.assign(static_cast<size_t>(packed_side) * packed_side, 0.0);
      if (segs.empty()) continue;
      size_t pos = 0;
      while (pos < segs.size()) {
        const int ti = q.segments()[segs[pos]].pair / n;
        std::fill(u.begin(), u.end(), 0.0);
        // All pairs (ti, *) in this cell.
        while (pos < segs.size() && q.segments()[segs[pos]].pair / n == ti) {
          const int pair = q.segments()[segs[pos]].pair;
          const int tr = pair % n;
          const PairGeometry g{rule.x[ti], rule.s_x[ti], rule.x[tr], rule.s_x[tr]};
          std::fill(t_pair.begin(), t_pair.end(), 0.0);
          for (; pos < segs.size() && q.segments()[segs[pos]].pair == pair; ++pos) {
            const PairQuadrature::Segment& seg = q.segments()[segs[pos]];
            for (int64_t i = seg.begin; i < seg.end; ++i) {
              const PairQuadrature::Node& node = q.nodes()[i];
              double theta_h, gamma;
              HalfVectorAt(g, node.delta, &theta_h, &gamma, nullptr);
              const double t = std::clamp(node.theta_h / table_step - cell, 0.0, 1.0);
              const DBrdfTerms terms = TermsAt(g.ci, g.cr, node.k_dot_h);
              const double coef[4] = {node.weight * (1 - t) * terms.normal,
                                      node.weight * t * terms.normal,
                                      node.weight * (1 - t) * terms.grazing,
                                      node.weight * t * terms.grazing};
              // a_s = e^{i s (delta - gamma)}, b_s' = e^{-i s' gamma}; the phase of T_ss' is
              // s delta - (s + s') gamma = s (delta - gamma) - s' gamma.
              const std::complex<double> ea = std::polar(1.0, node.delta - gamma);
              const std::complex<double> eb = std::polar(1.0, -gamma);
              a[order] = b[order] = 1.0;
              for (int s = 1; s <= order; ++s) {
                a[order + s] = a[order + s - 1] * ea;
                a[order - s] = std::conj(a[order + s]);
                b[order + s] = b[order + s - 1] * eb;
                b[order - s] = std::conj(b[order + s]);
              }
              for (int si = 0; si < span; ++si) {
                const double ra = a[si].real(), ia = a[si].imag();
                for (int e = 0; e < 4; ++e) {
                  double* row = &t_pair[(static_cast<size_t>(e) * span + si) * span];
                  const double cr_a = coef[e] * ra, ci_a = coef[e] * ia;
                  for (int sj = 0; sj < span; ++sj) row[sj] += cr_a * b[sj].real() - ci_a * b[sj].imag();
                }
              }
            }
          }
          // U[e][s][(s', l')] += w_r Theta_l'|s'|(tr) T[e][s][s'].
          const double wr = rule.weight[tr];
          const double* theta_r = q.ThetaPart(tr);
          for (int e = 0; e < 4; ++e) {
            for (int si = 0; si < span; ++si) {
              double* urow = &u[(static_cast<size_t>(e) * span + si) * packed_side];
              const double* trow = &t_pair[(static_cast<size_t>(e) * span + si) * span];
              for (int sj = 0; sj < span; ++sj) {
                const int abs_sp = std::abs(sj - order);
                const double value = wr * trow[sj];
                if (value == 0.0) continue;
                for (int lp = abs_sp; lp <= order; ++lp) {
                  urow[s_offset[sj] + lp - abs_sp] += value * theta_r[LegendreIndex(lp, abs_sp)];
                }
              }
            }
          }
        }
        // V[e][(s, l), (s', l')] += w_i Theta_l|s|(ti) U[e][s][(s', l')].
        const double wi = rule.weight[ti];
        const double* theta_i = q.ThetaPart(ti);
        for (int e = 0; e < 4; ++e) {
          for (int si = 0; si < span; ++si) {
            const int s = si - order, abs_s = std::abs(s);
            const double* urow = &u[(static_cast<size_t>(e) * span + si) * packed_side];
            for (int l = abs_s; l <= order; ++l) {
              const double f = wi * theta_i[LegendreIndex(l, abs_s)];
              double* vrow = &v[e][static_cast<size_t>(s_offset[si] + l - abs_s) * packed_side];
              for (int c = 0; c < packed_side; ++c) vrow[c] += f * urow[c];
            }
          }
        }
      }
    }
  });
  // Assembly into real tensor entries: z_kj = 2 pi sum alpha_ms alpha_m's' c_n e^{-i n phi_k} V.
  auto alphas = [](int m, int* s, std::complex<double>* alpha) {
    if (m == 0) {
      s[0] = 0;
      alpha[0] = 1.0;
      return 1;
    }
    const double r = M_SQRT1_2;
    const int am = std::abs(m);
    s[0] = am;
    s[1] = -am;
    if (m > 0) {
      alpha[0] = r;
      alpha[1] = r;
    } else {
      alpha[0] = std::complex<double>(0, -r);
      alpha[1] = std::complex<double>(0, r);
    }
    return 2;
  };
  auto fourier = [&](int nn) {
    if (nn == 0) return 1.0 / phi_samples;
    const double x = nn * M_PI / phi_samples;
    const double sinc = std::sin(x) / x;
    return sinc * sinc / phi_samples;
  };
  DBrdfProjection out;
  out.isotropic = false;
  const int columns = theta_samples * phi_samples;
  out.normal = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(size) * size, columns);
  out.grazing = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(size) * size, columns);
  for (int k = 0; k < size; ++k) {
    int l, m;
    ShDegreeOrder(k, &l, &m);
    int s[2];
    std::complex<double> alpha[2];
    const int ns = alphas(m, s, alpha);
    for (int j = 0; j < size; ++j) {
      int lp, mp;
      ShDegreeOrder(j, &lp, &mp);
      int sp[2];
      std::complex<double> alphap[2];
      const int nsp = alphas(mp, sp, alphap);
      const Eigen::Index row = static_cast<Eigen::Index>(k) * size + j;
      for (int a = 0; a < ns; ++a) {
        for (int b = 0; b < nsp; ++b) {
          const int nn = -(s[a] + sp[b]);
          const double cn = fourier(nn);
          if (std::abs(cn) < 1e-300) continue;
          const std::complex<double> weight = 2.0 * M_PI * alpha[a] * alphap[b] * cn;
          const size_t idx = packed(s[a], l, sp[b], lp);
          for (int kk = 0; kk < phi_samples; ++kk) {
            const double phase = -nn * 2.0 * M_PI * kk / phi_samples;
            const double factor = (weight * std::polar(1.0, phase)).real();
            if (factor == 0.0) continue;
            for (int cell = 0; cell < table_cells; ++cell) {
              const auto& v = per_cell[cell];
              out.normal(row, cell * phi_samples + kk) += factor * v[0][idx];
              out.normal(row, (cell + 1) * phi_samples + kk) += factor * v[1][idx];
              out.grazing(row, cell * phi_samples + kk) += factor * v[2][idx];
              out.grazing(row, (cell + 1) * phi_samples + kk) += factor * v[3][idx];
            }
          }
        }
      }
    }
  }
  // Diffuse: isotropic, expanded.
  std::vector<Eigen::MatrixXd> h(order + 1, Eigen::MatrixXd::Zero(n, n));
  for (int ti = 0; ti < n; ++ti) h[0].row(ti).setConstant(2.0 * rule.x[ti]);
  const Eigen::MatrixXd diffuse = IsotropicLayout(order).Expand(ContractIsotropic(q, h));
  out.diffuse.resize(static_cast<Eigen::Index>(size) * size);
  for (int k = 0; k < size; ++k) {
    for (int j = 0; j < size; ++j) out.diffuse[static_cast<Eigen::Index>(k) * size + j] = diffuse(k, j);
  }
  return out;
}

}  // namespace

DBrdfProjection ProjectDBrdfTable(const PairQuadrature& quadrature, int theta_samples,
                                  int phi_samples) {
  if (theta_samples < 2 || phi_samples < 1 ||
      quadrature.theta_h_cells() % (theta_samples - 1) != 0) {
    throw InputError("D-BRDF projection: theta_samples - 1 = " + std::to_string(theta_samples - 1) +
                     " must divide the quadrature's " + std::to_string(quadrature.theta_h_cells()) +
                     " half-vector cells, and phi_samples must be >= 1");
  }
  if (phi_samples == 1) return ProjectIsotropicTable(quadrature, theta_samples);
  return ProjectAnisotropicTable(quadrature, theta_samples, phi_samples);
}

std::array<Eigen::MatrixXd, 3> DBrdfTensor(const DBrdfProjection& projection, const DBrdfParams& params,
                                           int order) {
  const Eigen::Map<const Eigen::VectorXd> p(params.p_h.p.data(), static_cast<Eigen::Index>(params.p_h.p.size()));
  ZBRDF_ASSERT(p.size() == projection.normal.cols(), "table does not match the projection");
  const Eigen::VectorXd np = projection.normal * p, rp = projection.grazing * p;
  const int n = ShCount(order);
  std::array<Eigen::MatrixXd, 3> out;
  for (int ch = 0; ch < 3; ++ch) {
    const Eigen::VectorXd v = params.c[ch] * (params.f0 * np + rp) + params.kd[ch] * projection.diffuse;
    if (projection.isotropic) {
      out[ch] = IsotropicLayout(order).Expand(v);
    } else {
      out[ch].resize(n, n);
      for (int k = 0; k < n; ++k) {
        for (int j = 0; j < n; ++j) out[ch](k, j) = v[static_cast<Eigen::Index>(k) * n + j];
      }
    }
  }
  return out;
}

}  // namespace zbrdf
