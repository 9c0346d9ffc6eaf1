#include "brdf/ggx.h"

#include <cmath>

#include "brdf/fresnel.h"
#include "brdf/model_parameters.h"
#include "brdf/sampling.h"

namespace zbrdf {

GgxBrdf::GgxBrdf(double alpha_x, double alpha_y, const Rgb& f0, const Rgb& kd)
    : alpha_x_(alpha_x), alpha_y_(alpha_y), f0_(f0), kd_(kd) {
  RequirePositive("ggx", "alpha_x", alpha_x);
  RequirePositive("ggx", "alpha_y", alpha_y);
  RequireInUnitInterval("ggx", "F0", f0);
  RequireNonNegative("ggx", "kd", kd);
}

double GgxBrdf::D(const Vec3& h) const {
  if (h.z <= 0) return 0;
  const double sx = h.x / alpha_x_, sy = h.y / alpha_y_;
  const double q = sx * sx + sy * sy + h.z * h.z;
  return 1.0 / (M_PI * alpha_x_ * alpha_y_ * q * q);
}

double GgxBrdf::Lambda(const Vec3& w) const {
  const double tx = alpha_x_ * w.x, ty = alpha_y_ * w.y;
  const double tan2_alpha2 = (tx * tx + ty * ty) / (w.z * w.z);
  return 0.5 * (std::sqrt(1.0 + tan2_alpha2) - 1.0);
}

Rgb GgxBrdf::Eval(const Vec3& w_i, const Vec3& w_o) const {
  if (w_i.z <= 0 || w_o.z <= 0) return {};
  const Vec3 h = Normalize(w_i + w_o);
  const double g2 = 1.0 / (1.0 + Lambda(w_i) + Lambda(w_o));
  const double lobe = D(h) * g2 / (4.0 * w_i.z * w_o.z);
  return kd_ / M_PI + SchlickFresnel(f0_, Dot(w_o, h)) * lobe;
}

double GgxBrdf::SpecularProbability(const Vec3& w_o) const {
  return SpecularLobeProbability(SchlickFresnel(f0_, w_o.z).Average(), kd_.Average());
}

BrdfSample GgxBrdf::Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const {
  BrdfSample s;
  if (w_o.z <= 0) return s;
  s.w_i = SampleHalfVectorMixture(
      w_o, SpecularProbability(w_o), u_lobe, u0, u1, [&](double u, double v) {
        // Heitz 2018, listing 1: stretch w_o to the hemisphere configuration, sample a projected
        // disk warped by the visible fraction, unstretch the normal.
        const Vec3 v_h = Normalize(Vec3{alpha_x_ * w_o.x, alpha_y_ * w_o.y, w_o.z});
        const double len2 = v_h.x * v_h.x + v_h.y * v_h.y;
        const Vec3 t1 = len2 > 0 ? Vec3{-v_h.y, v_h.x, 0.0} / std::sqrt(len2) : Vec3{1.0, 0.0, 0.0};
        const Vec3 t2 = Cross(v_h, t1);
        const double r = std::sqrt(u);
        const double phi = 2.0 * M_PI * v;
        const double p1 = r * std::cos(phi);
        const double s_weight = 0.5 * (1.0 + v_h.z);
        const double p2 = (1.0 - s_weight) * std::sqrt(std::max(0.0, 1.0 - p1 * p1)) +
                          s_weight * r * std::sin(phi);
        const Vec3 n_h =
            p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1.0 - p1 * p1 - p2 * p2)) * v_h;
        return Normalize(Vec3{alpha_x_ * n_h.x, alpha_y_ * n_h.y, std::max(0.0, n_h.z)});
      });
  s.pdf = Pdf(w_o, s.w_i);
  return s;
}

double GgxBrdf::Pdf(const Vec3& w_o, const Vec3& w_i) const {
  if (w_o.z <= 0) return 0;
  // The visible-normal density D_wo(h) = G1(w_o) max(0, w_o.h) D(h) / cos(theta_o).
  const double g1 = 1.0 / (1.0 + Lambda(w_o));
  return HalfVectorMixturePdf(w_o, w_i, SpecularProbability(w_o), [&](const Vec3& h) {
    return g1 * std::max(0.0, Dot(w_o, h)) * D(h) / w_o.z;
  });
}

bool GgxBrdf::IsEnergyConserving() const { return kd_.Max() == 0; }

std::string GgxBrdf::Spec() const {
  const std::string tail = ",F0=" + FormatRgb(f0_) + ",kd=" + FormatRgb(kd_);
  if (alpha_x_ == alpha_y_) return "ggx:alpha=" + FormatDouble(alpha_x_) + tail;
  return "ggx:alpha_x=" + FormatDouble(alpha_x_) + ",alpha_y=" + FormatDouble(alpha_y_) + tail;
}

}  // namespace zbrdf
