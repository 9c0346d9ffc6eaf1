// A retro-reflective lobe over a Lambertian base, for tests and the stability suite: light
// returns toward where it came from (road signs, bead-coated fabrics), the opposite of a mirror.
//
//   f_r = kd / pi + kr (n + 1) / (2 pi) max(0, w_i . w_o)^n
//
// The lobe is the Phong cosine lobe about w_o instead of about the mirror direction; its factor
// normalizes it over the sphere of w_i (integral of max(0, cos a)^n dw = 2 pi / (n + 1)), so the
// directional albedo is at most kd + kr (the cosine factor is <= 1, and the part of the lobe
// below the horizon is lost). f_r is symmetric in w_i and w_o, hence reciprocal.
//
// Sampled as a mixture: the cosine lobe about w_o with probability kr / (kd + kr) (channel
// averages), else the cosine-weighted hemisphere.
#pragma once

#include <string>

#include "brdf/brdf.h"

namespace zbrdf {

class RetroBrdf final : public Brdf {
 public:
  // kd, kr >= 0 per channel and n >= 0, all finite; throws InputError otherwise.
  RetroBrdf(const Rgb& kd, const Rgb& kr, double exponent);

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override;
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const override;
  double Pdf(const Vec3& w_o, const Vec3& w_i) const override;
  double GlossyProbability(const Vec3& w_o) const override;
  bool IsReciprocal() const override { return true; }
  // True when kd + kr <= 1 in every channel.
  bool IsEnergyConserving() const override;
  // "retro:kd=..,kr=..,n=..".
  std::string Spec() const override;

 private:
  Rgb kd_, kr_;
  double exponent_;
  double retro_probability_;
};

}  // namespace zbrdf
