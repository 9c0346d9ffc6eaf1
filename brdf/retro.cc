#include "brdf/retro.h"

#include <algorithm>
#include <cmath>

#include "brdf/model_parameters.h"

namespace zbrdf {

RetroBrdf::RetroBrdf(const Rgb& kd, const Rgb& kr, double exponent)
    : kd_(kd), kr_(kr), exponent_(exponent) {
  RequireNonNegative("retro", "kd", kd);
  RequireNonNegative("retro", "kr", kr);
  RequireNonNegative("retro", "n", exponent);
  const double d = kd.Average(), r = kr.Average();
  retro_probability_ = d + r > 0 ? r / (d + r) : 0.0;
}

Rgb RetroBrdf::Eval(const Vec3& w_i, const Vec3& w_o) const {
  if (w_i.z <= 0 || w_o.z <= 0) return {};
  const double c = std::max(0.0, Dot(w_i, w_o));
  return kd_ / M_PI + kr_ * ((exponent_ + 1.0) / (2.0 * M_PI) * std::pow(c, exponent_));
}

BrdfSample RetroBrdf::Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const {
  BrdfSample s;
  if (w_o.z <= 0) return s;
  if (u_lobe < retro_probability_) {
    // Inverse CDF of the normalized cosine lobe about w_o: cos a = u^(1 / (n + 1)).
    const double cos_a = std::pow(u0, 1.0 / (exponent_ + 1.0));
    const double sin_a = std::sqrt(std::max(0.0, 1.0 - cos_a * cos_a));
    const double phi = 2.0 * M_PI * u1;
    Vec3 t, b;
    OrthonormalBasis(w_o, &t, &b);
    s.w_i = Normalize(t * (sin_a * std::cos(phi)) + b * (sin_a * std::sin(phi)) + w_o * cos_a);
  } else {
    s.w_i = SampleCosineHemisphere(u0, u1);
  }
  s.pdf = Pdf(w_o, s.w_i);
  return s;
}

double RetroBrdf::Pdf(const Vec3& w_o, const Vec3& w_i) const {
  if (w_o.z <= 0) return 0;
  const double c = std::max(0.0, Dot(w_i, w_o));
  return retro_probability_ * (exponent_ + 1.0) / (2.0 * M_PI) * std::pow(c, exponent_) +
         (1.0 - retro_probability_) * CosineHemispherePdf(w_i);
}

double RetroBrdf::GlossyProbability(const Vec3& w_o) const {
  return w_o.z > 0 ? retro_probability_ : 0.0;
}

bool RetroBrdf::IsEnergyConserving() const { return (kd_ + kr_).Max() <= 1; }

std::string RetroBrdf::Spec() const {
  return "retro:kd=" + FormatRgb(kd_) + ",kr=" + FormatRgb(kr_) + ",n=" + FormatDouble(exponent_);
}

}  // namespace zbrdf
