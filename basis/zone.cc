#include "basis/zone.h"

#include <cstdio>

#include "basis/error.h"

namespace zbrdf {

Zone::Zone(double theta_min_rad, double theta_max_rad)
    : theta_min_rad_(theta_min_rad), theta_max_rad_(theta_max_rad) {
  if (!std::isfinite(theta_min_rad) || !std::isfinite(theta_max_rad) || theta_min_rad < 0 ||
      theta_max_rad > M_PI / 2 + 1e-12 || theta_min_rad >= theta_max_rad) {
    char msg[200];
    std::snprintf(msg, sizeof(msg),
                  "zone [%g, %g] deg is not valid: need 0 <= theta_min < theta_max <= 90 deg",
                  RadToDeg(theta_min_rad), RadToDeg(theta_max_rad));
    throw InputError(msg);
  }
  theta_max_rad_ = std::min(theta_max_rad, M_PI / 2);
  cos_lower_ = std::cos(theta_max_rad_);
  cos_upper_ = std::cos(theta_min_rad_);
  if (theta_max_rad_ == M_PI / 2) cos_lower_ = 0.0;  // exact horizon, not 6e-17
}

Zone Zone::FromDegrees(double theta_min_deg, double theta_max_deg) {
  return Zone(DegToRad(theta_min_deg), DegToRad(theta_max_deg));
}

std::string Zone::ToString() const {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "[%.2f, %.2f] deg", RadToDeg(theta_min_rad_),
                RadToDeg(theta_max_rad_));
  return buf;
}

}  // namespace zbrdf
