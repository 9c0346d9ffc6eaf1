// Normalized Blinn-Phong: f_r = kd / pi + ks (n + 8) / (8 pi) (n.h)^n, with h the half vector.
// (n + 8) / (8 pi) is the usual approximate normalization (Akenine-Moller, Haines & Hoffman,
// "Real-Time Rendering", 3rd ed., section 7.6): the specular albedo at normal incidence is
// ks (n + 8) [2 (1 - 2^-(n+4)/2) / (n + 4) - (1 - 2^-(n+2)/2) / (n + 2)], which tends to ks from
// above (1.018 ks at n = 100). The model is reciprocal but not energy conserving.
//
// Sampling mixes the half-vector lobe p_h(h) = (n + 1) / (2 pi) (n.h)^n, reflected about h
// (pdf p_h / (4 |w_o.h|)), with cosine sampling for the diffuse part; the specular lobe is chosen
// with probability mean(ks) / (mean(ks) + mean(kd)).
#pragma once

#include <string>

#include "brdf/brdf.h"

namespace zbrdf {

class BlinnPhongBrdf final : public Brdf {
 public:
  // kd, ks >= 0 per channel; exponent n >= 0. Throws InputError otherwise (or for NaN).
  BlinnPhongBrdf(const Rgb& kd, const Rgb& ks, double exponent);

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override;
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const override;
  double Pdf(const Vec3& w_o, const Vec3& w_i) const override;
  double GlossyProbability(const Vec3&) const override { return specular_probability_; }
  bool IsReciprocal() const override { return true; }
  // False: the (n + 8) / (8 pi) normalization is approximate (see above).
  bool IsEnergyConserving() const override { return false; }
  bool IsIsotropic() const override { return true; }
  // "blinn-phong:kd=..,ks=..,n=..".
  std::string Spec() const override;

  const Rgb& kd() const { return kd_; }
  const Rgb& ks() const { return ks_; }
  double exponent() const { return exponent_; }

 private:
  Rgb kd_, ks_;
  double exponent_;
  double specular_probability_;
};

}  // namespace zbrdf
