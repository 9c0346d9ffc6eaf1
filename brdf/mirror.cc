#include "brdf/mirror.h"

#include "brdf/model_parameters.h"

namespace zbrdf {

MirrorBrdf::MirrorBrdf(const Rgb& reflectance) : reflectance_(reflectance) {
  RequireInUnitInterval("mirror", "R", reflectance);
}

Rgb MirrorBrdf::Eval(const Vec3& /*w_i*/, const Vec3& /*w_o*/) const { return {}; }

BrdfSample MirrorBrdf::Sample(const Vec3& w_o, double /*u_lobe*/, double /*u0*/,
                              double /*u1*/) const {
  BrdfSample s;
  if (w_o.z <= 0) return s;
  s.w_i = Vec3{-w_o.x, -w_o.y, w_o.z};
  s.pdf = 1.0;
  s.is_delta = true;
  s.delta_reflectance = reflectance_;
  return s;
}

double MirrorBrdf::Pdf(const Vec3& /*w_o*/, const Vec3& /*w_i*/) const { return 0; }

std::string MirrorBrdf::Spec() const { return "mirror:R=" + FormatRgb(reflectance_); }

}  // namespace zbrdf
