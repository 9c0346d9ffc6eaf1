// Lambertian (ideal diffuse) reflection: f_r = albedo / pi for every pair of directions above the
// horizon. albedo is the directional-hemispherical reflectance per channel.
//
// Sampled with the cosine-weighted hemisphere, which is exactly proportional to f_r cos(theta_i).
#pragma once

#include <string>

#include "brdf/brdf.h"

namespace zbrdf {

class LambertianBrdf final : public Brdf {
 public:
  // Throws InputError if a channel of albedo is negative or not finite. Albedos above 1 are
  // accepted (IsEnergyConserving() then says false).
  explicit LambertianBrdf(const Rgb& albedo);

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override;
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const override;
  double Pdf(const Vec3& w_o, const Vec3& w_i) const override;
  bool IsReciprocal() const override { return true; }
  // True when every channel of albedo is <= 1.
  bool IsEnergyConserving() const override;
  bool IsIsotropic() const override { return true; }
  // albedo / pi.
  std::optional<Rgb> ConstantValue() const override;
  // "lambert:albedo=A" (A one value or r,g,b).
  std::string Spec() const override;

  const Rgb& albedo() const { return albedo_; }

 private:
  Rgb albedo_;
};

}  // namespace zbrdf
