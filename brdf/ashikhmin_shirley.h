// Ashikhmin & Shirley's anisotropic Phong model (Ashikhmin & Shirley 2000, "An Anisotropic Phong
// BRDF Model", eqs. 4-5; Ghosh's thesis eq. 2.9), with the half vector h, k = w_i or w_o,
// phi the azimuth of h in the sample frame and Schlick's Fresnel F with F0 = Rs:
//   specular = sqrt((nu + 1)(nv + 1)) / (8 pi) (n.h)^(nu cos^2 phi + nv sin^2 phi)
//              / ((h.k) max(n.w_i, n.w_o)) F(k.h)
//   diffuse  = 28 Rd / (23 pi) (1 - Rs) (1 - (1 - n.w_i / 2)^5) (1 - (1 - n.w_o / 2)^5)
// nu shapes the lobe along the sample frame's x axis, nv along y.
//
// Reciprocal. Energy conserving when Rd <= 1 per channel, as the paper designs it and as the
// tests check by quadrature down to cos(theta_o) = 1e-3: the specular albedo is at most max F
// (p_h below integrates to 1, and cos(theta_i) / max(cos theta_i, cos theta_o) <= 1), and the
// diffuse albedo is Rd (1 - Rs) (1 - (1 - cos(theta_o) / 2)^5), which leaves room for it.
//
// Sampling (the paper's eq. 9): phi_h = atan2(sqrt(nu + 1) sin 2 pi u1, sqrt(nv + 1) cos 2 pi u1),
// cos(theta_h) = (1 - u0)^(1 / (nu cos^2 phi_h + nv sin^2 phi_h + 1)), with density
// p_h(h) = sqrt((nu + 1)(nv + 1)) / (2 pi) (n.h)^(nu cos^2 phi + nv sin^2 phi); w_o is reflected
// about h (pdf p_h / (4 |w_o.h|)). Mixed with cosine sampling for the diffuse term; the specular
// lobe is chosen with probability proportional to mean F(n.w_o), the diffuse one to
// mean(Rd (1 - Rs)).
#pragma once

#include <string>

#include "brdf/brdf.h"

namespace zbrdf {

class AshikhminShirleyBrdf final : public Brdf {
 public:
  // rd, rs >= 0 per channel, rs <= 1; nu, nv >= 0. Throws InputError otherwise.
  AshikhminShirleyBrdf(const Rgb& rd, const Rgb& rs, double nu, double nv);

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override;
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const override;
  double Pdf(const Vec3& w_o, const Vec3& w_i) const override;
  double GlossyProbability(const Vec3& w_o) const override { return SpecularProbability(w_o); }
  bool IsReciprocal() const override { return true; }
  // True when rd <= 1 in every channel.
  bool IsEnergyConserving() const override;
  bool IsIsotropic() const override { return nu_ == nv_; }
  // "as:rd=..,rs=..,nu=..,nv=..".
  std::string Spec() const override;

  const Rgb& rd() const { return rd_; }
  const Rgb& rs() const { return rs_; }
  double nu() const { return nu_; }
  double nv() const { return nv_; }

 private:
  // p_h(h) above, for a unit h in the upper hemisphere.
  double HalfVectorDensity(const Vec3& h) const;
  double SpecularProbability(const Vec3& w_o) const;

  Rgb rd_, rs_;
  double nu_, nv_;
};

}  // namespace zbrdf
