#include "fitting/peak_projection.h"

#include <algorithm>
#include <cmath>

#include "basis/error.h"
#include "basis/legendre.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "basis/quadrature.h"
#include "basis/zonal_basis.h"

namespace zbrdf {
namespace {

// The projection is summed in this many fixed slices of its nodes, whatever the thread count,
// so that results do not depend on the machine.
constexpr int kSlices = 4;

// Per-column accumulator of the azimuthal (or inner) sums, reset through a list of the columns
// touched.
class ColumnAccumulator {
 public:
  ColumnAccumulator(int columns, int width) : width_(width), sums_(static_cast<size_t>(columns) * width, 0.0), seen_(columns, 0) {}
  double* At(int column) {
    if (!seen_[column]) {
      seen_[column] = 1;
      touched_.push_back(column);
    }
    return &sums_[static_cast<size_t>(column) * width_];
  }
  const std::vector<int>& touched() const { return touched_; }
  const double* Sums(int column) const { return &sums_[static_cast<size_t>(column) * width_]; }
  void Reset() {
    for (int c : touched_) {
      std::fill_n(&sums_[static_cast<size_t>(c) * width_], width_, 0.0);
      seen_[c] = 0;
    }
    touched_.clear();
  }

 private:
  int width_;
  std::vector<double> sums_;
  std::vector<char> seen_;
  std::vector<int> touched_;
};

}  // namespace

void PeakProjectionOptions::Validate() const {
  OptionChecker check("PeakProjectionOptions");
  check.InRange("window_inner_deg", window_inner_deg, 0.5, 20.0)
      .InRange("window_outer_deg", window_outer_deg, window_inner_deg + 0.5, 30.0)
      .InRange("half_theta_per_piece", half_theta_per_piece, 2, 64)
      .InRange("half_phi", half_phi, 16, 4096)
      .Nested("pair", pair)  // every bad field in one message, the pair rule's under "pair."
      .ThrowIfInvalid();
}

PeakProjector::PeakProjector(const Zone& zone, int order, const PeakProjectionOptions& options)
    : zone_(zone), order_(order), options_(options) {
  options.Validate();
  pair_ = std::make_unique<PairQuadrature>(zone, order, options.pair);
  const CosThetaRule& rule = pair_->theta_rule();
  const int n = pair_->theta_nodes();
  // The h rule on [0, window_outer_deg].
  std::vector<double> pieces_deg = {0.0, 0.25, 1.0, 3.0};
  while (!pieces_deg.empty() && pieces_deg.back() >= options.window_outer_deg) pieces_deg.pop_back();
  pieces_deg.push_back(options.window_outer_deg);
  const GaussLegendreRule gl = GaussLegendre(options.half_theta_per_piece);
  struct H {
    Vec3 h;
    double weight, theta;
  };
  std::vector<H> hs;
  for (size_t p = 0; p + 1 < pieces_deg.size(); ++p) {
    const double lo = DegToRad(pieces_deg[p]), hi = DegToRad(pieces_deg[p + 1]);
    for (size_t q = 0; q < gl.nodes.size(); ++q) {
      const double theta = 0.5 * (lo + hi) + 0.5 * (hi - lo) * gl.nodes[q];
      const double w = 0.5 * (hi - lo) * gl.weights[q] * std::sin(theta) * 2.0 * M_PI /
                       options.half_phi;
      for (int j = 0; j < options.half_phi; ++j) {
        hs.push_back({SphericalDirection(theta, 2.0 * M_PI * (j + 0.5) / options.half_phi), w,
                      theta});
      }
    }
  }
  half_begin_.assign(n + 1, 0);
  for (int r = 0; r < n; ++r) {
    half_begin_[r] = static_cast<int>(half_nodes_.size());
    const Vec3 w_r{rule.s_x[r], 0.0, rule.x[r]};
    for (const H& h : hs) {
      const double cos_rh = Dot(w_r, h.h);
      if (cos_rh <= 0) continue;
      const Vec3 w_i = Normalize(2.0 * cos_rh * h.h - w_r);
      if (!zone.ContainsCosTheta(w_i.z)) continue;
      const double weight = 4.0 * cos_rh * h.weight * Window(h.theta);
      if (weight > 0) half_nodes_.push_back({r, w_i, weight, h.theta});
    }
  }
  half_begin_[n] = static_cast<int>(half_nodes_.size());
}

PeakProjector::~PeakProjector() = default;

double PeakProjector::Window(double theta_h) const {
  const double x = std::clamp((RadToDeg(theta_h) - options_.window_inner_deg) /
                                  (options_.window_outer_deg - options_.window_inner_deg),
                              0.0, 1.0);
  return 1.0 - x * x * (3.0 - 2.0 * x);
}

Eigen::MatrixXd PeakProjector::Matrix(const Stencil& stencil, int columns) const {
  const int L = order_, n = pair_->theta_nodes();
  const IsotropicLayout layout(L);
  const CosThetaRule& rule = pair_->theta_rule();
  // wx * Theta_lm at each theta node.
  auto theta = [&](int t, int l, int m) {
    return rule.weight[t] * pair_->ThetaPart(t)[LegendreIndex(l, m)];
  };
  const ZonalBasis zb(zone_, L);
  const int pairs = n * n;
  std::vector<Eigen::MatrixXd> slices(kSlices);
  ParallelFor(kSlices, 1, [&](int64_t s0, int64_t s1) {
    std::vector<double> cm(L + 1), part(LegendreCount(L));
    std::array<int, 8> cols;
    std::array<double, 8> wts;
    for (int64_t s = s0; s < s1; ++s) {
      Eigen::MatrixXd out = Eigen::MatrixXd::Zero(layout.size(), columns);
      // Pair rule, g (1 - window): per pair, azimuthal sums per column and m.
      ColumnAccumulator acc(columns, L + 1);
      for (int p = static_cast<int>(s * pairs / kSlices); p < (s + 1) * pairs / kSlices; ++p) {
        for (int g = pair_->PairSegmentBegin(p); g < pair_->PairSegmentBegin(p + 1); ++g) {
          const PairQuadrature::Segment& seg = pair_->segments()[g];
          for (int64_t i = seg.begin; i < seg.end; ++i) {
            const PairQuadrature::Node& node = pair_->nodes()[i];
            const double keep = 1.0 - Window(node.theta_h);
            if (keep <= 0) continue;
            Vec3 w_i, w_r;
            pair_->Directions(p, node, &w_i, &w_r);
            const int k = stencil(w_i, w_r, cols.data(), wts.data());
            if (k == 0) continue;
            CosMultiplesOfCos(L, node.cos_delta, cm.data());
            const double base = node.weight * w_i.z * keep;
            for (int e = 0; e < k; ++e) {
              double* a = acc.At(cols[e]);
              for (int m = 0; m <= L; ++m) a[m] += base * wts[e] * cm[m];
            }
          }
        }
        const int ti = p / n, tr = p % n;
        for (int c : acc.touched()) {
          const double* a = acc.Sums(c);
          for (int m = 0; m <= L; ++m) {
            if (a[m] == 0) continue;
            for (int l = m; l <= L; ++l) {
              const double tl = 2.0 * M_PI * theta(ti, l, m) * a[m];
              for (int lp = m; lp <= L; ++lp) out(layout.Index(m, l, lp), c) += tl * theta(tr, lp, m);
            }
          }
        }
        acc.Reset();
      }
      // h rule, g window: per exitant node, inner sums per column and (l, m).
      ColumnAccumulator inner(columns, LegendreCount(L));
      for (int r = static_cast<int>(s * n / kSlices); r < (s + 1) * n / kSlices; ++r) {
        const Vec3 w_r{rule.s_x[r], 0.0, rule.x[r]};
        for (int q = half_begin_[r]; q < half_begin_[r + 1]; ++q) {
          const HalfNode& node = half_nodes_[q];
          const int k = stencil(node.w_i, w_r, cols.data(), wts.data());
          if (k == 0) continue;
          zb.EvalThetaPart(node.w_i.z, part.data());
          CosMultiples(L, std::atan2(node.w_i.y, node.w_i.x), cm.data());
          const double base = node.weight * node.w_i.z;
          for (int e = 0; e < k; ++e) {
            double* a = inner.At(cols[e]);
            for (int m = 0; m <= L; ++m) {
              for (int l = m; l <= L; ++l) a[LegendreIndex(l, m)] += base * wts[e] * part[LegendreIndex(l, m)] * cm[m];
            }
          }
        }
        for (int c : inner.touched()) {
          const double* a = inner.Sums(c);
          for (int m = 0; m <= L; ++m) {
            for (int l = m; l <= L; ++l) {
              const double v = 2.0 * M_PI * a[LegendreIndex(l, m)];
              if (v == 0) continue;
              for (int lp = m; lp <= L; ++lp) out(layout.Index(m, l, lp), c) += v * theta(r, lp, m);
            }
          }
        }
        inner.Reset();
      }
      slices[s] = std::move(out);
    }
  });
  Eigen::MatrixXd total = std::move(slices[0]);
  for (int s = 1; s < kSlices; ++s) total += slices[s];
  return total;
}

std::array<Eigen::VectorXd, 3> PeakProjector::ProjectBrdf(const Brdf& brdf) const {
  // The sums of Matrix() with g itself in place of a stencil.
  const int L = order_, n = pair_->theta_nodes();
  const IsotropicLayout layout(L);
  const CosThetaRule& rule = pair_->theta_rule();
  auto theta = [&](int t, int l, int m) {
    return rule.weight[t] * pair_->ThetaPart(t)[LegendreIndex(l, m)];
  };
  const ZonalBasis zb(zone_, L);
  std::array<Eigen::VectorXd, 3> out;
  for (auto& v : out) v = Eigen::VectorXd::Zero(layout.size());
  std::vector<std::array<Eigen::VectorXd, 3>> slices(kSlices);
  const int pairs = n * n;
  ParallelFor(kSlices, 1, [&](int64_t s0, int64_t s1) {
    std::vector<double> cm(L + 1), part(LegendreCount(L));
    std::vector<Vec3> wi, wr;
    std::vector<Rgb> f;
    for (int64_t s = s0; s < s1; ++s) {
      std::array<Eigen::VectorXd, 3> acc;
      for (auto& v : acc) v = Eigen::VectorXd::Zero(layout.size());
      std::vector<std::array<double, 3>> hm(L + 1);
      for (int p = static_cast<int>(s * pairs / kSlices); p < (s + 1) * pairs / kSlices; ++p) {
        for (auto& h : hm) h = {0, 0, 0};
        wi.clear();
        wr.clear();
        std::vector<const PairQuadrature::Node*> nodes;
        for (int g = pair_->PairSegmentBegin(p); g < pair_->PairSegmentBegin(p + 1); ++g) {
          const PairQuadrature::Segment& seg = pair_->segments()[g];
          for (int64_t i = seg.begin; i < seg.end; ++i) {
            const PairQuadrature::Node& node = pair_->nodes()[i];
            if (Window(node.theta_h) >= 1.0) continue;
            Vec3 a, b;
            pair_->Directions(p, node, &a, &b);
            wi.push_back(a);
            wr.push_back(b);
            nodes.push_back(&node);
          }
        }
        if (nodes.empty()) continue;
        f.resize(wi.size());
        brdf.EvalBatch(wi, wr, f);
        for (size_t k = 0; k < nodes.size(); ++k) {
          CosMultiplesOfCos(L, nodes[k]->cos_delta, cm.data());
          const double base = nodes[k]->weight * wi[k].z * (1.0 - Window(nodes[k]->theta_h));
          for (int m = 0; m <= L; ++m) {
            for (int c = 0; c < 3; ++c) hm[m][c] += base * cm[m] * f[k][c];
          }
        }
        const int ti = p / n, tr = p % n;
        for (int m = 0; m <= L; ++m) {
          for (int l = m; l <= L; ++l) {
            for (int lp = m; lp <= L; ++lp) {
              const double t = 2.0 * M_PI * theta(ti, l, m) * theta(tr, lp, m);
              for (int c = 0; c < 3; ++c) acc[c][layout.Index(m, l, lp)] += t * hm[m][c];
            }
          }
        }
      }
      std::vector<std::array<double, 3>> inner(LegendreCount(L));
      for (int r = static_cast<int>(s * n / kSlices); r < (s + 1) * n / kSlices; ++r) {
        const Vec3 w_r{rule.s_x[r], 0.0, rule.x[r]};
        const int b0 = half_begin_[r], b1 = half_begin_[r + 1];
        if (b1 == b0) continue;
        wi.resize(b1 - b0);
        wr.assign(b1 - b0, w_r);
        for (int q = b0; q < b1; ++q) wi[q - b0] = half_nodes_[q].w_i;
        f.resize(wi.size());
        brdf.EvalBatch(wi, wr, f);
        for (auto& v : inner) v = {0, 0, 0};
        for (int q = b0; q < b1; ++q) {
          const HalfNode& node = half_nodes_[q];
          zb.EvalThetaPart(node.w_i.z, part.data());
          CosMultiples(L, std::atan2(node.w_i.y, node.w_i.x), cm.data());
          const double base = node.weight * node.w_i.z;
          for (int m = 0; m <= L; ++m) {
            for (int l = m; l <= L; ++l) {
              const double w = base * part[LegendreIndex(l, m)] * cm[m];
              for (int c = 0; c < 3; ++c) inner[LegendreIndex(l, m)][c] += w * f[q - b0][c];
            }
          }
        }
        for (int m = 0; m <= L; ++m) {
          for (int l = m; l <= L; ++l) {
            for (int lp = m; lp <= L; ++lp) {
              const double t = 2.0 * M_PI * theta(r, lp, m);
              for (int c = 0; c < 3; ++c) acc[c][layout.Index(m, l, lp)] += t * inner[LegendreIndex(l, m)][c];
            }
          }
        }
      }
      slices[s] = std::move(acc);
    }
  });
  for (int s = 0; s < kSlices; ++s) {
    for (int c = 0; c < 3; ++c) out[c] += slices[s][c];
  }
  return out;
}

}  // namespace zbrdf
