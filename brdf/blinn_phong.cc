#include "brdf/blinn_phong.h"

#include <cmath>

#include "brdf/model_parameters.h"
#include "brdf/sampling.h"

namespace zbrdf {

BlinnPhongBrdf::BlinnPhongBrdf(const Rgb& kd, const Rgb& ks, double exponent)
    : kd_(kd), ks_(ks), exponent_(exponent) {
  RequireNonNegative("blinn-phong", "kd", kd);
  RequireNonNegative("blinn-phong", "ks", ks);
  RequireNonNegative("blinn-phong", "n", exponent);
  specular_probability_ = SpecularLobeProbability(ks.Average(), kd.Average());
}

Rgb BlinnPhongBrdf::Eval(const Vec3& w_i, const Vec3& w_o) const {
  if (w_i.z <= 0 || w_o.z <= 0) return {};
  const Vec3 h = Normalize(w_i + w_o);
  const double lobe = (exponent_ + 8.0) / (8.0 * M_PI) * std::pow(h.z, exponent_);
  return kd_ / M_PI + ks_ * lobe;
}

BrdfSample BlinnPhongBrdf::Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const {
  BrdfSample s;
  if (w_o.z <= 0) return s;
  s.w_i =
      SampleHalfVectorMixture(w_o, specular_probability_, u_lobe, u0, u1, [&](double u, double v) {
        // Inverse CDF of (n + 1) cos^n(theta_h) over cos(theta_h) in [0, 1] (Ghosh eq. 2.28).
        const double cos_h = std::pow(u, 1.0 / (exponent_ + 1.0));
        const double sin_h = std::sqrt(std::max(0.0, 1.0 - cos_h * cos_h));
        const double phi = 2.0 * M_PI * v;
        return Vec3{sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h};
      });
  s.pdf = Pdf(w_o, s.w_i);
  return s;
}

double BlinnPhongBrdf::Pdf(const Vec3& w_o, const Vec3& w_i) const {
  if (w_o.z <= 0) return 0;
  return HalfVectorMixturePdf(w_o, w_i, specular_probability_, [&](const Vec3& h) {
    return (exponent_ + 1.0) / (2.0 * M_PI) * std::pow(h.z, exponent_);
  });
}

std::string BlinnPhongBrdf::Spec() const {
  return "blinn-phong:kd=" + FormatRgb(kd_) + ",ks=" + FormatRgb(ks_) +
         ",n=" + FormatDouble(exponent_);
}

}  // namespace zbrdf
