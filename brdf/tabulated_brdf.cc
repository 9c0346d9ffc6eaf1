#include "brdf/tabulated_brdf.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "basis/error.h"
#include "basis/parallel.h"

namespace zbrdf {

HalfDiffAngles HalfDiffOf(const Vec3& w_i, const Vec3& w_o) {
  HalfDiffAngles a;
  const Vec3 sum = w_i + w_o;
  const double length = Length(sum);
  if (!(length > 0)) return a;
  const Vec3 h = sum / length;
  a.theta_h = std::acos(std::clamp(h.z, -1.0, 1.0));
  // The folded coordinates are the same for (w_i, w_o) and (w_o, w_i) in exact arithmetic, not
  // after rounding: d is taken from the smaller of the two in the order (x, z, y), which
  // mirroring y keeps, so that swapping the directions gives the same bits (tables are then
  // reciprocal exactly).
  const Vec3& w = std::tie(w_o.x, w_o.z, w_o.y) < std::tie(w_i.x, w_i.z, w_i.y) ? w_o : w_i;
  // d = R_y(-theta_h) R_z(-phi_h) w, with cos/sin of the angles taken from h directly.
  const double rho = std::sqrt(h.x * h.x + h.y * h.y);
  const double cp = rho > 0 ? h.x / rho : 1.0, sp = rho > 0 ? h.y / rho : 0.0;
  const double ct = h.z, st = rho;
  const double x = cp * w.x + sp * w.y, y = -sp * w.x + cp * w.y, z = w.z;
  const double dx = ct * x - st * z, dz = st * x + ct * z;
  a.theta_d = std::acos(std::clamp(dz, -1.0, 1.0));
  double phi = std::abs(std::atan2(y, dx));  // bilateral symmetry: phi_d -> -phi_d
  if (phi > 0.5 * M_PI) phi = M_PI - phi;    // reciprocity: phi_d -> phi_d + pi
  a.phi_d = phi;
  return a;
}

HalfDiffGrid::HalfDiffGrid(int theta_h_nodes, int theta_d_nodes, int phi_d_nodes)
    : nh_(theta_h_nodes), nd_(theta_d_nodes), np_(phi_d_nodes) {
  for (int n : {nh_, nd_, np_}) {
    if (n < 2 || n > 512) {
      throw InputError("half/difference grid " + ToString() +
                       ": every node count must be in [2, 512]");
    }
  }
}

std::string HalfDiffGrid::ToString() const {
  return std::to_string(nh_) + " x " + std::to_string(nd_) + " x " + std::to_string(np_);
}

double HalfDiffGrid::ThetaHalf(int ih) const {
  const double u = static_cast<double>(ih) / (nh_ - 1);
  return 0.5 * M_PI * u * u;
}
double HalfDiffGrid::ThetaDiff(int id) const { return 0.5 * M_PI * id / (nd_ - 1); }
double HalfDiffGrid::PhiDiff(int ip) const { return 0.5 * M_PI * ip / (np_ - 1); }

void HalfDiffGrid::Directions(int index, Vec3* w_i, Vec3* w_o) const {
  const int ip = index % np_, id = (index / np_) % nd_, ih = index / (np_ * nd_);
  const double th = ThetaHalf(ih), td = ThetaDiff(id), pd = PhiDiff(ip);
  const Vec3 d{std::sin(td) * std::cos(pd), std::sin(td) * std::sin(pd), std::cos(td)};
  const double c = std::cos(th), s = std::sin(th);
  const Vec3 wi{c * d.x + s * d.z, d.y, -s * d.x + c * d.z};
  const Vec3 h{s, 0.0, c};
  *w_i = wi;
  *w_o = 2.0 * Dot(wi, h) * h - wi;
}

bool HalfDiffGrid::NodeAboveHorizon(int index) const {
  Vec3 wi, wo;
  Directions(index, &wi, &wo);
  // Nodes exactly on the horizon (theta_h = pi/2 at theta_d = 0, theta_h + theta_d = pi/2 at
  // phi_d = 0) come out of Directions() with z of order 1e-17 of either sign, cos(pi/2) being
  // 6e-17: they are not strictly above it. A model there is at exact grazing, where a microfacet
  // model is ~1e15 (f ~ 1 / cos theta); the margin keeps such values out of tables.
  constexpr double kOnHorizon = 1e-12;
  return wi.z > kOnHorizon && wo.z > kOnHorizon;
}

HalfDiffGrid::Stencil HalfDiffGrid::StencilOf(const HalfDiffAngles& a) const {
  auto locate = [](double x, int n, int* i0, double* t) {
    x = std::clamp(x, 0.0, static_cast<double>(n - 1));
    *i0 = std::min(static_cast<int>(x), n - 2);
    *t = x - *i0;
  };
  int i0, j0, k0;
  double tu, tv, tw;
  locate(std::sqrt(std::max(0.0, a.theta_h) / (0.5 * M_PI)) * (nh_ - 1), nh_, &i0, &tu);
  locate(a.theta_d / (0.5 * M_PI) * (nd_ - 1), nd_, &j0, &tv);
  locate(a.phi_d / (0.5 * M_PI) * (np_ - 1), np_, &k0, &tw);
  Stencil s;
  int n = 0;
  for (int di = 0; di < 2; ++di) {
    for (int dj = 0; dj < 2; ++dj) {
      for (int dk = 0; dk < 2; ++dk, ++n) {
        s.index[n] = Index(i0 + di, j0 + dj, k0 + dk);
        s.weight[n] = (di ? tu : 1 - tu) * (dj ? tv : 1 - tv) * (dk ? tw : 1 - tw);
      }
    }
  }
  return s;
}

template <typename T>
void FillBelowHorizon(const HalfDiffGrid& grid, std::span<T> values) {
  for (int ih = 0; ih < grid.theta_h_nodes(); ++ih) {
    for (int ip = 0; ip < grid.phi_d_nodes(); ++ip) {
      int last_valid = -1;
      for (int id = 0; id < grid.theta_d_nodes(); ++id) {
        const int index = grid.Index(ih, id, ip);
        if (grid.NodeAboveHorizon(index)) {
          last_valid = index;
        } else if (last_valid >= 0) {
          values[index] = values[last_valid];
        } else if (ih > 0) {
          // Only the theta_h = pi/2 row has no node above the horizon: it holds the previous
          // row's values (already filled), so that grazing pairs interpolate between values of
          // the material too.
          values[index] = values[grid.Index(ih - 1, id, ip)];
        }
      }
    }
  }
}
template void FillBelowHorizon<Rgb>(const HalfDiffGrid&, std::span<Rgb>);
template void FillBelowHorizon<float>(const HalfDiffGrid&, std::span<float>);
template void FillBelowHorizon<double>(const HalfDiffGrid&, std::span<double>);

std::vector<Rgb> TabulateBrdf(const Brdf& brdf, const HalfDiffGrid& grid) {
  std::vector<Rgb> values(grid.size());
  ParallelFor(grid.size(), 256, [&](int64_t n0, int64_t n1) {
    std::vector<Vec3> wi(2 * (n1 - n0)), wo(2 * (n1 - n0));
    std::vector<Rgb> f(wi.size());
    for (int64_t n = n0; n < n1; ++n) {
      Vec3 a, b;
      grid.Directions(static_cast<int>(n), &a, &b);
      // The mirror pair (phi_d -> pi - phi_d, i.e. y -> -y) of the same node.
      wi[2 * (n - n0)] = a;
      wo[2 * (n - n0)] = b;
      wi[2 * (n - n0) + 1] = {b.x, -b.y, b.z};
      wo[2 * (n - n0) + 1] = {a.x, -a.y, a.z};
    }
    brdf.EvalBatch(wi, wo, f);
    for (int64_t n = n0; n < n1; ++n) {
      values[n] = 0.5 * (f[2 * (n - n0)] + f[2 * (n - n0) + 1]);
    }
  });
  FillBelowHorizon(grid, std::span<Rgb>(values));
  return values;
}

TabulatedBrdf::TabulatedBrdf(HalfDiffGrid grid, std::vector<Rgb> values, std::vector<Rgb> sigma,
                             std::string spec)
    : grid_(grid), values_(std::move(values)), sigma_(std::move(sigma)), spec_(std::move(spec)) {
  if (static_cast<int>(values_.size()) != grid_.size() ||
      (!sigma_.empty() && static_cast<int>(sigma_.size()) != grid_.size())) {
    throw InputError("tabulated BRDF " + spec_ + ": the grid " + grid_.ToString() + " needs " +
                     std::to_string(grid_.size()) + " values per channel, got " +
                     std::to_string(values_.size()) + " (and " + std::to_string(sigma_.size()) +
                     " uncertainties)");
  }
  for (const auto* v : {&values_, &sigma_}) {
    for (size_t n = 0; n < v->size(); ++n) {
      const Rgb& c = (*v)[n];
      if (!c.IsFinite() || c.r < 0 || c.g < 0 || c.b < 0) {
        throw InputError("tabulated BRDF " + spec_ + ": node " + std::to_string(n) + " has " +
                         (v == &values_ ? "value" : "uncertainty") + " (" + std::to_string(c.r) +
                         ", " + std::to_string(c.g) + ", " + std::to_string(c.b) +
                         "); values must be finite and >= 0");
      }
    }
  }
  FitProxySampler();
}

namespace {
Rgb Blend(const HalfDiffGrid& grid, const std::vector<Rgb>& v, const Vec3& w_i, const Vec3& w_o) {
  const HalfDiffGrid::Stencil s = grid.StencilOf(HalfDiffOf(w_i, w_o));
  Rgb out;
  for (int k = 0; k < 8; ++k) out += s.weight[k] * v[s.index[k]];
  return out;
}
}  // namespace

Rgb TabulatedBrdf::Eval(const Vec3& w_i, const Vec3& w_o) const {
  if (w_i.z <= 0 || w_o.z <= 0) return Rgb();
  return Blend(grid_, values_, w_i, w_o);
}

Rgb TabulatedBrdf::EvalSigma(const Vec3& w_i, const Vec3& w_o) const {
  if (sigma_.empty() || w_i.z <= 0 || w_o.z <= 0) return Rgb();
  return Blend(grid_, sigma_, w_i, w_o);
}

}  // namespace zbrdf
