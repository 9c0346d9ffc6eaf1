// An importance-sampling proposal for isotropic BRDFs without an analytic sampler (MERL tables,
// measured-material networks).
//
// At construction the BRDF is probed along the mirror direction for viewing angles theta_o =
// 0, 0.15, ..., 1.5 rad: the luminance of f_r(w_i, w_o) as w_i moves away from the mirror
// direction r = (-w_o.x, -w_o.y, w_o.z), in and across the plane of incidence, at offsets from
// 1e-3 to 1.2 rad. The part above the BRDF's floor (its minimum over the probes) is treated as a
// lobe symmetric about r, and matched by two Phong lobes whose median angles are the angles
// holding a quarter and three quarters of its energy (a sharp core and broad wings); the lobe's
// and the floor's energies give the probability P of sampling the lobes. For a given w_o the
// proposal is the mixture
//   p(w_i) = P/2 sum_k (m_k + 1) / (2 pi) max(0, w_i.r)^m_k + (1 - P) max(0, cos theta_i) / pi
// with m_k and P interpolated (log m_k and P linearly in theta_o) between the probes. P is kept
// in [0.05, 0.95] so that no lobe is ever dropped; m_k in [1, 1e6].
//
// It is only a proposal for Monte Carlo with multiple importance sampling: Pdf() is exactly the
// density Sample() draws from, but need not match f_r cos theta_i closely. Probing costs about
// 800 evaluations of the BRDF.
#pragma once

#include <vector>

#include "fitting/brdf.h"

namespace zbrdf {

class LobeProxySampler {
 public:
  struct Probe {
    double theta_o_rad = 0;
    double median_angle_rad[2] = {0, 0};  // of the two Phong lobes, about r
    double exponent[2] = {1, 1};          // m_k: cos^(m_k + 1)(median angle) = 1/2
    double specular_probability = 0;      // P
  };
  // The proposal for one viewing angle.
  struct Mixture {
    double exponent[2] = {1, 1};
    double lobe_probability = 0;
  };

  // Probes brdf (assumed isotropic); it is used only during construction.
  explicit LobeProxySampler(const Brdf& brdf);

  // The mixture above; no sample (pdf = 0) for w_o below the horizon.
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const;
  double Pdf(const Vec3& w_o, const Vec3& w_i) const;

  // m_k and P for a viewing direction with the given polar angle.
  Mixture MixtureFor(double theta_o_rad) const;
  const std::vector<Probe>& probes() const { return probes_; }

 private:
  std::vector<Probe> probes_;          // at increasing, evenly spaced theta_o
  std::vector<double> log_exponents_;  // log m_k per probe, for the interpolation
};

}  // namespace zbrdf
