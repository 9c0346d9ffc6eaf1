// A perfect (flat, smooth) mirror: all reflected light leaves along the mirror direction
// w_i = (-w_o.x, -w_o.y, w_o.z), scaled by the reflectance R. The simulator uses it as the flat
// calibration mirror.
//
// As a function f_r is a Dirac delta, so Eval() and Pdf() return 0; Sample() returns the mirror
// direction with is_delta, pdf = 1 and delta_reflectance = R (for w_o above the horizon).
#pragma once

#include <string>

#include "brdf/brdf.h"

namespace zbrdf {

class MirrorBrdf final : public Brdf {
 public:
  // reflectance in [0, 1] per channel; throws InputError otherwise.
  explicit MirrorBrdf(const Rgb& reflectance);

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override;
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const override;
  double Pdf(const Vec3& w_o, const Vec3& w_i) const override;
  bool IsReciprocal() const override { return true; }
  bool IsEnergyConserving() const override { return true; }
  bool IsDelta() const override { return true; }
  // "mirror:R=..".
  std::string Spec() const override;

  const Rgb& reflectance() const { return reflectance_; }

 private:
  Rgb reflectance_;
};

}  // namespace zbrdf
