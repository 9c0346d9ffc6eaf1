#include "brdf/lambertian.h"

#include <cmath>

#include "brdf/model_parameters.h"

namespace zbrdf {

LambertianBrdf::LambertianBrdf(const Rgb& albedo) : albedo_(albedo) {
  RequireNonNegative("lambert", "albedo", albedo);
}

Rgb LambertianBrdf::Eval(const Vec3& w_i, const Vec3& w_o) const {
  if (w_i.z <= 0 || w_o.z <= 0) return {};
  return albedo_ / M_PI;
}

BrdfSample LambertianBrdf::Sample(const Vec3& w_o, double /*u_lobe*/, double u0, double u1) const {
  BrdfSample s;
  if (w_o.z <= 0) return s;
  s.w_i = SampleCosineHemisphere(u0, u1);
  s.pdf = CosineHemispherePdf(s.w_i);
  return s;
}

double LambertianBrdf::Pdf(const Vec3& w_o, const Vec3& w_i) const {
  return w_o.z > 0 ? CosineHemispherePdf(w_i) : 0.0;
}

std::optional<Rgb> LambertianBrdf::ConstantValue() const { return albedo_ / M_PI; }

bool LambertianBrdf::IsEnergyConserving() const { return albedo_.Max() <= 1; }

std::string LambertianBrdf::Spec() const { return "lambert:albedo=" + FormatRgb(albedo_); }

}  // namespace zbrdf
