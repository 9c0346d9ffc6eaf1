// The distribution-based BRDF (D-BRDF; Ashikhmin & Premoze 2007, "Distribution-based BRDFs";
// Ghosh's thesis eq. 2.13, docs/design.md section 4):
//   f_r = c p(h) F(k.h) / (k1.n + k2.n - (k1.n)(k2.n)) + kd / pi
// with k1 = w_i, k2 = w_o, h their half vector, F Schlick's Fresnel with a scalar F0, c an RGB
// scale and p(h) a tabulated half-vector distribution normalized so that
// integral p(h) (h.n) dw_h = 1 over the upper hemisphere.
//
// p(h) is what fitting extracts from measurements (at retro-reflection k1 = k2 = h,
// p(h) = f_r(h, h) (2 cos theta_h - cos^2 theta_h) / (c F0)), so it is exposed as a plain table.
//
// Sampling inverts a 2-D CDF over (theta_h, phi_h) cells of the table (thesis section 3.4.1): a
// cell is chosen with probability proportional to max(p at its corners) times its projected solid
// angle, h is uniform in (cos theta_h, phi_h) within the cell, and w_o is reflected about h, so
// pdf(w_i) = p_cell / (4 |w_o.h|) with p_cell the cell's probability over its solid angle.
// Mixed with cosine sampling for kd; the specular lobe is chosen with probability proportional to
// 4 mean(c) F(cos theta_o) (the lobe's albedo at normal incidence for a narrow p), the diffuse one
// to mean(kd).
#pragma once

#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "brdf/sampling.h"

namespace zbrdf {

// p(h) in 1/sr on a grid of nodes: theta_h,j = j (pi/2) / (theta_samples - 1) for
// j = 0 .. theta_samples - 1 (both ends included), and phi_h,k = k 2 pi / phi_samples for
// k = 0 .. phi_samples - 1 (periodic). phi_samples = 1 is an isotropic (1-D) table. Values in
// between are interpolated linearly in theta_h and (periodically) in phi_h.
struct HalfVectorTable {
  int theta_samples = 0;  // >= 2
  int phi_samples = 1;    // >= 1
  std::vector<double> p;  // p[j * phi_samples + k] >= 0, in 1/sr

  // An isotropic table from p at theta_samples = p_by_theta.size() nodes.
  static HalfVectorTable Isotropic(std::vector<double> p_by_theta);
  // The GGX (Trowbridge-Reitz) distribution of roughness alpha,
  //   D(theta_h) = 1 / (pi alpha^2 (sin^2 theta_h / alpha^2 + cos^2 theta_h)^2),
  // at theta_samples nodes, normalized (Normalize()): the half-vector table of a glossy D-BRDF
  // for tests and benchmarks (the thesis's figure 3.11 material).
  static HalfVectorTable Ggx(double alpha, int theta_samples = 91);

  double ThetaStep() const;  // radians between theta nodes
  double PhiStep() const;    // radians between phi nodes
  double At(int j, int k) const { return p[static_cast<size_t>(j) * phi_samples + k]; }

  // Interpolated p at the half vector with polar angle theta_h in [0, pi/2] (clamped) and
  // azimuth phi_h (any real; taken modulo 2 pi).
  double Eval(double theta_h_rad, double phi_h_rad) const;

  // integral p(h) cos(theta_h) dw_h over the upper hemisphere of the interpolated table, in
  // closed form (exact up to rounding).
  double NormalizationIntegral() const;
  // Divides p by NormalizationIntegral(). Throws NumericalError if the integral is not positive
  // (an all-zero table).
  void Normalize();

  // Empty if the table is well formed, else what is wrong ("dbrdf: p has 7 values, expected
  // theta_samples * phi_samples = 8").
  std::string Problems() const;
};

struct DBrdfParams {
  HalfVectorTable p_h;  // normalized: integral p(h) (h.n) dw_h = 1
  Rgb c{1.0};           // >= 0 per channel
  double f0 = 0.04;     // Schlick's F0, in [0, 1]
  Rgb kd;               // >= 0 per channel
};

class DBrdf final : public Brdf {
 public:
  // Throws InputError if the table is malformed, not normalized (|integral - 1| > 1e-9; the
  // message says to call HalfVectorTable::Normalize() and fold the scale into c) or a parameter
  // is out of range.
  explicit DBrdf(DBrdfParams params);

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override;
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const override;
  double Pdf(const Vec3& w_o, const Vec3& w_i) const override;
  double GlossyProbability(const Vec3& w_o) const override { return SpecularProbability(w_o); }
  bool IsReciprocal() const override { return true; }
  // False: the albedo depends on c and the shape of p; nothing bounds it by construction.
  bool IsEnergyConserving() const override { return false; }
  bool IsIsotropic() const override { return params_.p_h.phi_samples == 1; }
  // "dbrdf:c=..,F0=..,kd=..,theta_samples=N,phi_samples=M,p=p0,p1,..." (every table value).
  std::string Spec() const override;

  const DBrdfParams& params() const { return params_; }
  const HalfVectorTable& table() const { return params_.p_h; }
  const Rgb& c() const { return params_.c; }
  double f0() const { return params_.f0; }
  const Rgb& kd() const { return params_.kd; }

  // Solid-angle density of the half-vector sampler at unit h (z >= 0).
  double HalfVectorPdf(const Vec3& h) const;

 private:
  double SpecularProbability(const Vec3& w_o) const;

  DBrdfParams params_;
  std::vector<double> cos_theta_nodes_;  // cos(theta_h,j)
  Distribution2D cells_;                 // over (phi cell, theta cell)
  std::vector<double> cell_density_;     // [j * phi_samples + k]: the sampler's density in cell
};

}  // namespace zbrdf
