#include "brdf/ashikhmin_shirley.h"

#include <cmath>

#include "brdf/fresnel.h"
#include "brdf/model_parameters.h"
#include "brdf/sampling.h"

namespace zbrdf {
namespace {

// 1 - (1 - cos / 2)^5, the diffuse term's angular factor (Ashikhmin & Shirley 2000, eq. 5).
double DiffuseFactor(double cos_theta) {
  const double m = 1.0 - 0.5 * cos_theta;
  const double m2 = m * m;
  return 1.0 - m2 * m2 * m;
}

}  // namespace

AshikhminShirleyBrdf::AshikhminShirleyBrdf(const Rgb& rd, const Rgb& rs, double nu, double nv)
    : rd_(rd), rs_(rs), nu_(nu), nv_(nv) {
  RequireNonNegative("as", "rd", rd);
  RequireInUnitInterval("as", "rs", rs);
  RequireNonNegative("as", "nu", nu);
  RequireNonNegative("as", "nv", nv);
}

double AshikhminShirleyBrdf::HalfVectorDensity(const Vec3& h) const {
  // nu cos^2 phi + nv sin^2 phi = (nu hx^2 + nv hy^2) / (hx^2 + hy^2); at h = n the power is 1
  // whatever the exponent.
  const double sin2 = h.x * h.x + h.y * h.y;
  const double exponent = sin2 > 0 ? (nu_ * h.x * h.x + nv_ * h.y * h.y) / sin2 : nu_;
  return std::sqrt((nu_ + 1.0) * (nv_ + 1.0)) / (2.0 * M_PI) * std::pow(h.z, exponent);
}

Rgb AshikhminShirleyBrdf::Eval(const Vec3& w_i, const Vec3& w_o) const {
  if (w_i.z <= 0 || w_o.z <= 0) return {};
  const Vec3 h = Normalize(w_i + w_o);
  const double cos_kh = Dot(w_i, h);
  // specular = p_h(h) / (4 (h.k) max(n.w_i, n.w_o)) F(k.h).
  const double lobe = HalfVectorDensity(h) / (4.0 * cos_kh * std::max(w_i.z, w_o.z));
  const Rgb specular = SchlickFresnel(rs_, cos_kh) * lobe;
  const double angular = 28.0 / (23.0 * M_PI) * DiffuseFactor(w_i.z) * DiffuseFactor(w_o.z);
  const Rgb diffuse{rd_.r * (1.0 - rs_.r), rd_.g * (1.0 - rs_.g), rd_.b * (1.0 - rs_.b)};
  return specular + diffuse * angular;
}

double AshikhminShirleyBrdf::SpecularProbability(const Vec3& w_o) const {
  const Rgb diffuse{rd_.r * (1.0 - rs_.r), rd_.g * (1.0 - rs_.g), rd_.b * (1.0 - rs_.b)};
  return SpecularLobeProbability(SchlickFresnel(rs_, w_o.z).Average(), diffuse.Average());
}

BrdfSample AshikhminShirleyBrdf::Sample(const Vec3& w_o, double u_lobe, double u0,
                                        double u1) const {
  BrdfSample s;
  if (w_o.z <= 0) return s;
  s.w_i = SampleHalfVectorMixture(
      w_o, SpecularProbability(w_o), u_lobe, u0, u1, [&](double u, double v) {
        const double t = 2.0 * M_PI * v;
        const double phi =
            std::atan2(std::sqrt(nu_ + 1.0) * std::sin(t), std::sqrt(nv_ + 1.0) * std::cos(t));
        const double c = std::cos(phi), d = std::sin(phi);
        const double cos_h = std::pow(1.0 - u, 1.0 / (nu_ * c * c + nv_ * d * d + 1.0));
        const double sin_h = std::sqrt(std::max(0.0, 1.0 - cos_h * cos_h));
        return Vec3{sin_h * c, sin_h * d, cos_h};
      });
  s.pdf = Pdf(w_o, s.w_i);
  return s;
}

double AshikhminShirleyBrdf::Pdf(const Vec3& w_o, const Vec3& w_i) const {
  if (w_o.z <= 0) return 0;
  return HalfVectorMixturePdf(w_o, w_i, SpecularProbability(w_o),
                              [&](const Vec3& h) { return HalfVectorDensity(h); });
}

bool AshikhminShirleyBrdf::IsEnergyConserving() const { return rd_.Max() <= 1; }

std::string AshikhminShirleyBrdf::Spec() const {
  return "as:rd=" + FormatRgb(rd_) + ",rs=" + FormatRgb(rs_) + ",nu=" + FormatDouble(nu_) +
         ",nv=" + FormatDouble(nv_);
}

}  // namespace zbrdf
