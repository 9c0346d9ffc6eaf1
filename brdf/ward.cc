#include "brdf/ward.h"

#include <cmath>

#include "brdf/model_parameters.h"
#include "brdf/sampling.h"

namespace zbrdf {

WardBrdf::WardBrdf(const Rgb& rho_d, const Rgb& rho_s, double alpha_x, double alpha_y)
    : rho_d_(rho_d), rho_s_(rho_s), alpha_x_(alpha_x), alpha_y_(alpha_y) {
  RequireNonNegative("ward", "rho_d", rho_d);
  RequireNonNegative("ward", "rho_s", rho_s);
  RequirePositive("ward", "alpha_x", alpha_x);
  RequirePositive("ward", "alpha_y", alpha_y);
  specular_probability_ = SpecularLobeProbability(rho_s.Average(), rho_d.Average());
}

double WardBrdf::SlopeGaussian(const Vec3& h) const {
  // tan^2(delta) cos^2(phi) = hx^2 / hz^2 and tan^2(delta) sin^2(phi) = hy^2 / hz^2, for any
  // positive scale of h.
  const double sx = h.x / alpha_x_, sy = h.y / alpha_y_;
  return std::exp(-(sx * sx + sy * sy) / (h.z * h.z));
}

Rgb WardBrdf::Eval(const Vec3& w_i, const Vec3& w_o) const {
  if (w_i.z <= 0 || w_o.z <= 0) return {};
  const double lobe =
      SlopeGaussian(w_i + w_o) / (4.0 * M_PI * alpha_x_ * alpha_y_ * std::sqrt(w_i.z * w_o.z));
  return rho_d_ / M_PI + rho_s_ * lobe;
}

BrdfSample WardBrdf::Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const {
  BrdfSample s;
  if (w_o.z <= 0) return s;
  s.w_i =
      SampleHalfVectorMixture(w_o, specular_probability_, u_lobe, u0, u1, [&](double u, double v) {
        const double t = 2.0 * M_PI * v;
        const double phi = std::atan2(alpha_y_ * std::sin(t), alpha_x_ * std::cos(t));
        const double c = std::cos(phi) / alpha_x_, d = std::sin(phi) / alpha_y_;
        const double tan_h = std::sqrt(-std::log1p(-u) / (c * c + d * d));
        return Normalize(Vec3{tan_h * std::cos(phi), tan_h * std::sin(phi), 1.0});
      });
  s.pdf = Pdf(w_o, s.w_i);
  return s;
}

double WardBrdf::Pdf(const Vec3& w_o, const Vec3& w_i) const {
  if (w_o.z <= 0) return 0;
  return HalfVectorMixturePdf(w_o, w_i, specular_probability_, [&](const Vec3& h) {
    if (!(h.z > 0)) return 0.0;
    return SlopeGaussian(h) / (M_PI * alpha_x_ * alpha_y_ * h.z * h.z * h.z);
  });
}

std::string WardBrdf::Spec() const {
  return "ward:rho_d=" + FormatRgb(rho_d_) + ",rho_s=" + FormatRgb(rho_s_) +
         ",alpha_x=" + FormatDouble(alpha_x_) + ",alpha_y=" + FormatDouble(alpha_y_);
}

}  // namespace zbrdf
