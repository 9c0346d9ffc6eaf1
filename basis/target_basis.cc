#include "basis/target_basis.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "basis/error.h"
#include "basis/legendre.h"
#include "basis/spherical_harmonics.h"
#include "basis/zonal_basis.h"

namespace zbrdf {

std::string TargetName(TargetKind kind) {
  switch (kind) {
    case TargetKind::kSh: return "sh";
    case TargetKind::kShEven: return "sh-even";
    case TargetKind::kShOdd: return "sh-odd";
    case TargetKind::kHsh: return "hsh";
  }
  return "?";
}

TargetKind ParseTargetName(const std::string& name) {
  for (TargetKind k : {TargetKind::kSh, TargetKind::kShEven, TargetKind::kShOdd, TargetKind::kHsh}) {
    if (TargetName(k) == name) return k;
  }
  throw InputError("unknown target basis '" + name + "'; use sh, sh-even, sh-odd or hsh");
}

namespace {
bool Present(TargetKind kind, int l, int m) {
  const int parity = (l + std::abs(m)) % 2;
  switch (kind) {
    case TargetKind::kShEven: return parity == 0;
    case TargetKind::kShOdd: return parity == 1;
    default: return true;
  }
}
}  // namespace

TargetBasis::TargetBasis(TargetKind kind, int order) : kind_(kind), order_(order) {
  if (order < 0 || order > kMaxLegendreDegree) {
    throw InputError("target basis order " + std::to_string(order) + " is out of range [0, " +
                     std::to_string(kMaxLegendreDegree) + "]");
  }
  index_of_sh_.assign(ShCount(order), -1);
  for (int l = 0; l <= order; ++l) {
    for (int m = -l; m <= l; ++m) {
      if (!Present(kind, l, m)) continue;
      index_of_sh_[ShIndex(l, m)] = static_cast<int>(degree_.size());
      degree_.push_back(l);
      m_.push_back(m);
    }
  }
}

int TargetBasis::Index(int l, int m) const {
  if (l < 0 || l > order_ || std::abs(m) > l) return -1;
  return index_of_sh_[ShIndex(l, m)];
}

std::vector<int> TargetBasis::DegreesForOrder(int abs_m) const {
  std::vector<int> out;
  for (int l = abs_m; l <= order_; ++l) {
    if (Present(kind_, l, abs_m)) out.push_back(l);
  }
  return out;
}

void TargetBasis::EvalThetaFactor(int abs_m, double x, double s_x, double* out) const {
  std::array<double, kMaxLegendreDegree + 1> p;
  if (kind_ == TargetKind::kHsh) {
    // H_lm = ZB of [0, 90] deg: t = 2x - 1, 1 - t = 2(1 - x), 1 + t = 2x, factor sqrt(2).
    if (x < 0) {
      std::fill(out, out + DegreesForOrder(abs_m).size(), 0.0);
      return;
    }
    const double one_minus_t = 2.0 * (1.0 - x), one_plus_t = 2.0 * x;
    const double t = one_minus_t < one_plus_t ? 1.0 - one_minus_t : one_plus_t - 1.0;
    NormalizedLegendreOrder(order_, abs_m, t, std::sqrt(one_minus_t * one_plus_t), p.data());
    for (int l = abs_m; l <= order_; ++l) out[l - abs_m] = std::sqrt(2.0) * p[l - abs_m];
    return;
  }
  NormalizedLegendreOrder(order_, abs_m, x, s_x, p.data());
  int k = 0;
  for (int l = abs_m; l <= order_; ++l) {
    if (Present(kind_, l, abs_m)) out[k++] = p[l - abs_m];
  }
}

void TargetBasis::Eval(const Vec3& w, double* out) const {
  std::array<double, ShCount(kMaxLegendreDegree)> sh;
  if (kind_ == TargetKind::kHsh) {
    static const Zone kHemisphere(0.0, M_PI / 2);
    if (w.z < 0) {
      std::fill(out, out + size(), 0.0);
      return;
    }
    ZonalBasis(kHemisphere, order_).Eval(w, sh.data());
  } else {
    EvalShAll(order_, w, sh.data());
  }
  for (int k = 0; k < size(); ++k) out[k] = sh[ShIndex(degree_[k], m_[k])];
}

}  // namespace zbrdf
