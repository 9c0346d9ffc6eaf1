// The bases zonal coefficients are converted to (docs/design.md section 3, items 3-4).
//
//   sh       all real SH Y_lm, l <= order.
//   sh-even  Y_lm with l + m even: even under z -> -z, the even extension below the horizon.
//   sh-odd   Y_lm with l + m odd: odd under z -> -z, for data that vanish at the horizon
//            (cos-weighted BRDF slices).
//   hsh      hemispherical harmonics (Gautron et al. 2004): the ZB of the zone [0, 90] deg,
//            orthonormal over the upper hemisphere, zero below it.
// Functions are ordered by ShIndex(l, m) with the absent (l, m) skipped. Coefficients refer to
// the functions exactly as defined here (sh-even and sh-odd keep the full-sphere SH
// normalization; they are not rescaled to the hemisphere).
#pragma once

#include <string>
#include <vector>

#include "basis/vec3.h"

namespace zbrdf {

enum class TargetKind { kSh, kShEven, kShOdd, kHsh };

std::string TargetName(TargetKind kind);
// "sh", "sh-even", "sh-odd", "hsh"; throws InputError naming the accepted values.
TargetKind ParseTargetName(const std::string& name);

class TargetBasis {
 public:
  TargetBasis(TargetKind kind, int order);

  TargetKind kind() const { return kind_; }
  int order() const { return order_; }
  int size() const { return static_cast<int>(degree_.size()); }
  int degree(int k) const { return degree_[k]; }
  int azimuthal_order(int k) const { return m_[k]; }
  // Position of (l, m) in this basis, or -1 if absent.
  int Index(int l, int m) const;
  // Degrees l present for azimuthal order +-abs_m, ascending.
  std::vector<int> DegreesForOrder(int abs_m) const;

  // All functions at unit vector w (ordering as above).
  void Eval(const Vec3& w, double* out) const;
  // The theta factor for azimuthal order abs_m, for each degree in DegreesForOrder(abs_m):
  // T_lm(w) = factor(cos theta) * {1 (m = 0), sqrt(2) cos(m phi) (m > 0), sqrt(2) sin(|m| phi)}.
  // x = cos theta, s_x = sqrt(1 - x^2) (passed in to avoid cancellation).
  void EvalThetaFactor(int abs_m, double x, double s_x, double* out) const;

 private:
  TargetKind kind_;
  int order_;
  std::vector<int> degree_, m_;
  std::vector<int> index_of_sh_;  // ShIndex -> position or -1
};

}  // namespace zbrdf
