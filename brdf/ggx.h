// Cook-Torrance microfacet reflection with the GGX (Trowbridge-Reitz) distribution, plus a
// Lambertian term (Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces",
// eqs. 20, 33, 34; Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based
// BRDFs", eq. 99 for the height-correlated Smith term):
//   f_r = kd / pi + D(h) G2(w_i, w_o) F(w_o.h) / (4 cos(theta_i) cos(theta_o))
//   D(h) = 1 / (pi ax ay (hx^2 / ax^2 + hy^2 / ay^2 + hz^2)^2)
//   G2 = 1 / (1 + Lambda(w_i) + Lambda(w_o)),
//   Lambda(w) = (sqrt(1 + (ax^2 wx^2 + ay^2 wy^2) / wz^2) - 1) / 2
// F is Schlick's with F0 (RGB). ax, ay are the roughnesses along the sample frame's x and y axes
// (alpha = ax = ay for the isotropic model).
//
// Reciprocal. The specular term alone is energy conserving (its albedo is at most max F; Heitz
// 2014, section 6); adding kd > 0 is not (the two terms ignore each other).
//
// Sampling draws the distribution of visible normals (Heitz 2018, "Sampling the GGX Distribution
// of Visible Normals", JCGT 7(4)), D_wo(h) = G1(w_o) max(0, w_o.h) D(h) / cos(theta_o), and
// reflects w_o about h, so pdf = G1(w_o) D(h) / (4 cos(theta_o)): proportional to the specular
// term up to F and G2 / G1. Mixed with cosine sampling for kd; the specular lobe is chosen with
// probability proportional to mean F(cos theta_o), the diffuse one to mean(kd).
#pragma once

#include <string>

#include "brdf/brdf.h"

namespace zbrdf {

class GgxBrdf final : public Brdf {
 public:
  // alpha_x, alpha_y > 0; f0 in [0, 1] per channel; kd >= 0 per channel. Throws InputError
  // otherwise.
  GgxBrdf(double alpha_x, double alpha_y, const Rgb& f0, const Rgb& kd);

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override;
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const override;
  double Pdf(const Vec3& w_o, const Vec3& w_i) const override;
  double GlossyProbability(const Vec3& w_o) const override { return SpecularProbability(w_o); }
  bool IsReciprocal() const override { return true; }
  // True when kd is black (see above).
  bool IsEnergyConserving() const override;
  bool IsIsotropic() const override { return alpha_x_ == alpha_y_; }
  // "ggx:alpha=..,F0=..,kd=.." when isotropic, else "ggx:alpha_x=..,alpha_y=..,F0=..,kd=..".
  std::string Spec() const override;

  // The microfacet distribution D(h) in 1/sr (projected: integral D(h) (h.n) dw_h = 1) and the
  // Smith Lambda function, exposed for fitting code and tests.
  double D(const Vec3& h) const;
  double Lambda(const Vec3& w) const;

  double alpha_x() const { return alpha_x_; }
  double alpha_y() const { return alpha_y_; }
  const Rgb& f0() const { return f0_; }
  const Rgb& kd() const { return kd_; }

 private:
  double SpecularProbability(const Vec3& w_o) const;

  double alpha_x_, alpha_y_;
  Rgb f0_, kd_;
};

}  // namespace zbrdf
