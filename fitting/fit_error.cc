#include "fitting/fit_error.h"

#include <algorithm>
#include <array>
#include <iterator>
#include <cmath>
#include <vector>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "basis/quadrature.h"

namespace zbrdf {

CosineWeightedFn CosineWeightedOf(const Brdf& brdf) {
  return [&brdf](const Vec3& w_o, std::span<const Vec3> w_i, std::span<Rgb> f_hat) {
    std::vector<Vec3> wo(w_i.size(), w_o);
    brdf.EvalBatch(w_i, wo, f_hat);
    for (size_t k = 0; k < w_i.size(); ++k) f_hat[k] = f_hat[k] * std::max(0.0, w_i[k].z);
  };
}

namespace {

struct ThetaNode {
  double x, weight;  // cos(theta) and its weight
  bool in_zone;
};

// Gauss-Legendre in cos(theta) on [0, a], [a, b], [b, 1] with about `total` nodes.
std::vector<ThetaNode> SplitRule(const Zone& zone, int total) {
  const double a = zone.cos_lower(), b = zone.cos_upper();
  const double pieces[3][2] = {{0.0, a}, {a, b}, {b, 1.0}};
  std::vector<ThetaNode> nodes;
  for (int p = 0; p < 3; ++p) {
    const double lo = pieces[p][0], hi = pieces[p][1];
    if (hi - lo <= 1e-12) continue;
    const int n = std::max(4, static_cast<int>(std::lround(total * (hi - lo))));
    const GaussLegendreRule gl = GaussLegendre(n);
    for (int i = 0; i < n; ++i) {
      nodes.push_back({0.5 * (lo + hi) + 0.5 * (hi - lo) * gl.nodes[i], 0.5 * (hi - lo) * gl.weights[i], p == 1});
    }
  }
  return nodes;
}

}  // namespace

void BrdfComparisonOptions::Validate() const {
  OptionChecker check("BrdfComparisonOptions");
  check.AtLeast("half_theta_per_piece", half_theta_per_piece, 2)
      .AtLeast("half_phi", half_phi, 8)
      .AtLeast("exitant_theta", exitant_theta, 2)
      .AtLeast("exitant_phi", exitant_phi, 1)
      .ThrowIfInvalid();
}

BrdfComparison CompareBrdfs(const CosineWeightedFn& model, const CosineWeightedFn& truth,
                            const Zone& zone, const BrdfComparisonOptions& options) {
  options.Validate();
  // The half-vector rule (polar angle from the normal, any w_o).
  static constexpr double kPiecesDeg[] = {0, 0.25, 1, 3, 8, 20, 45, 90};
  const GaussLegendreRule gl = GaussLegendre(options.half_theta_per_piece);
  std::vector<Vec3> h;
  std::vector<double> weight_h;  // dw_h
  for (size_t p = 0; p + 1 < std::size(kPiecesDeg); ++p) {
    const double lo = DegToRad(kPiecesDeg[p]), hi = DegToRad(kPiecesDeg[p + 1]);
    for (size_t q = 0; q < gl.nodes.size(); ++q) {
      const double theta = 0.5 * (lo + hi) + 0.5 * (hi - lo) * gl.nodes[q];
      const double w = 0.5 * (hi - lo) * gl.weights[q] * std::sin(theta) * 2.0 * M_PI / options.half_phi;
      for (int j = 0; j < options.half_phi; ++j) {
        h.push_back(SphericalDirection(theta, 2.0 * M_PI * (j + 0.5) / options.half_phi));
        weight_h.push_back(w);
      }
    }
  }
  struct Exitant {
    Vec3 w;
    double weight;
    bool in_zone;
  };
  std::vector<Exitant> w_o;
  for (const ThetaNode& t : SplitRule(zone, options.exitant_theta)) {
    const double s = std::sqrt(std::max(0.0, 1.0 - t.x * t.x));
    for (int j = 0; j < options.exitant_phi; ++j) {
      const double phi = 2.0 * M_PI * j / options.exitant_phi;
      w_o.push_back({{s * std::cos(phi), s * std::sin(phi), t.x},
                     t.weight * 2.0 * M_PI / options.exitant_phi,
                     t.in_zone});
    }
  }
  struct Sums {
    double diff_in = 0, norm_in = 0, diff_out = 0, norm_out = 0, negative = 0, measure = 0;
    double diff_80 = 0, norm_80 = 0;
    // Per channel: whole hemisphere, theta <= 80 deg, zone.
    std::array<double, 3> diff_c{}, norm_c{}, diff_80_c{}, norm_80_c{}, diff_in_c{}, norm_in_c{};
  };
  const double cos80 = std::cos(DegToRad(80.0));
  std::vector<Sums> sums(w_o.size());
  ParallelFor(static_cast<int64_t>(w_o.size()), 1, [&](int64_t o0, int64_t o1) {
    std::vector<Vec3> w_i;
    std::vector<double> weight;
    std::vector<Rgb> fm, ft;
    for (int64_t o = o0; o < o1; ++o) {
      const Vec3& wo = w_o[o].w;
      w_i.clear();
      weight.clear();
      for (size_t k = 0; k < h.size(); ++k) {
        const double cos_oh = Dot(wo, h[k]);
        if (cos_oh <= 0) continue;
        const Vec3 wi = 2.0 * cos_oh * h[k] - wo;
        if (wi.z <= 0) continue;
        w_i.push_back(Normalize(wi));
        weight.push_back(4.0 * cos_oh * weight_h[k] * w_o[o].weight);
      }
      fm.resize(w_i.size());
      ft.resize(w_i.size());
      model(wo, w_i, fm);
      truth(wo, w_i, ft);
      Sums& s = sums[o];
      for (size_t k = 0; k < w_i.size(); ++k) {
        double d2 = 0, t2 = 0;
        const bool in = w_o[o].in_zone && zone.ContainsCosTheta(w_i[k].z);
        const bool within_80 = wo.z >= cos80 && w_i[k].z >= cos80;
        for (int ch = 0; ch < 3; ++ch) {
          const double d = fm[k][ch] - ft[k][ch];
          const double dd = weight[k] * d * d, tt = weight[k] * ft[k][ch] * ft[k][ch];
          d2 += d * d;
          t2 += ft[k][ch] * ft[k][ch];
          s.diff_c[ch] += dd;
          s.norm_c[ch] += tt;
          if (within_80) {
            s.diff_80_c[ch] += dd;
            s.norm_80_c[ch] += tt;
          }
          if (in) {
            s.diff_in_c[ch] += dd;
            s.norm_in_c[ch] += tt;
          }
        }
        if (in) {
          s.diff_in += weight[k] * d2;
          s.norm_in += weight[k] * t2;
        } else {
          s.diff_out += weight[k] * d2;
          s.norm_out += weight[k] * t2;
        }
        if (within_80) {
          s.diff_80 += weight[k] * d2;
          s.norm_80 += weight[k] * t2;
        }
        if (fm[k].r < 0 || fm[k].g < 0 || fm[k].b < 0) s.negative += weight[k];
        s.measure += weight[k];
      }
    }
  });
  Sums total;
  for (const Sums& s : sums) {
    total.diff_in += s.diff_in;
    total.norm_in += s.norm_in;
    total.diff_out += s.diff_out;
    total.norm_out += s.norm_out;
    total.negative += s.negative;
    total.measure += s.measure;
    total.diff_80 += s.diff_80;
    total.norm_80 += s.norm_80;
    for (int ch = 0; ch < 3; ++ch) {
      total.diff_c[ch] += s.diff_c[ch];
      total.norm_c[ch] += s.norm_c[ch];
      total.diff_80_c[ch] += s.diff_80_c[ch];
      total.norm_80_c[ch] += s.norm_80_c[ch];
      total.diff_in_c[ch] += s.diff_in_c[ch];
      total.norm_in_c[ch] += s.norm_in_c[ch];
    }
  }
  auto ratio = [](double d, double n) { return n > 0 ? std::sqrt(d / n) : (d > 0 ? INFINITY : 0.0); };
  BrdfComparison c;
  c.cosine_l2 = ratio(total.diff_in + total.diff_out, total.norm_in + total.norm_out);
  c.cosine_l2_80 = ratio(total.diff_80, total.norm_80);
  c.in_zone = ratio(total.diff_in, total.norm_in);
  c.has_outside = zone.theta_min_rad() > 0 || zone.theta_max_rad() < 0.5 * M_PI;
  c.outside_zone = c.has_outside ? ratio(total.diff_out, total.norm_out) : 0.0;
  c.negative_fraction = total.measure > 0 ? total.negative / total.measure : 0.0;
  for (int ch = 0; ch < 3; ++ch) {
    c.cosine_l2_channel_mean += ratio(total.diff_c[ch], total.norm_c[ch]) / 3.0;
    c.cosine_l2_80_channel_mean += ratio(total.diff_80_c[ch], total.norm_80_c[ch]) / 3.0;
    c.in_zone_channel_mean += ratio(total.diff_in_c[ch], total.norm_in_c[ch]) / 3.0;
  }
  return c;
}

}  // namespace zbrdf
