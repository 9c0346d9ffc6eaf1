// Schlick's approximation of Fresnel reflectance (Schlick 1994, "An Inexpensive BRDF Model for
// Physically-based Rendering", eq. 15): F(cos) = F0 + (1 - F0) (1 - cos)^5, where F0 is the
// reflectance at normal incidence and cos is the cosine between a direction (light or view) and
// the microfacet normal h. cos is clamped to [0, 1].
#pragma once

#include <algorithm>

#include "basis/vec3.h"

namespace zbrdf {

// (1 - cos)^5, the weight Schlick's approximation puts on (1 - F0).
inline double SchlickWeight(double cos_theta) {
  const double m = 1.0 - std::clamp(cos_theta, 0.0, 1.0);
  const double m2 = m * m;
  return m2 * m2 * m;
}

inline double SchlickFresnel(double f0, double cos_theta) {
  return f0 + (1.0 - f0) * SchlickWeight(cos_theta);
}

inline Rgb SchlickFresnel(const Rgb& f0, double cos_theta) {
  const double w = SchlickWeight(cos_theta);
  return {f0.r + (1.0 - f0.r) * w, f0.g + (1.0 - f0.g) * w, f0.b + (1.0 - f0.b) * w};
}

}  // namespace zbrdf
