// A spherical zone of directions: theta in [theta_min, theta_max], all azimuths.
//
// The rig measures incident and exitant directions over one such zone (docs/design.md section 1).
// Angles are radians from the sample normal (+z); zones lie in the upper hemisphere.
#pragma once

#include <cmath>
#include <string>

namespace zbrdf {

class Zone {
 public:
  // Throws InputError unless 0 <= theta_min < theta_max <= pi/2 (all finite).
  Zone(double theta_min_rad, double theta_max_rad);
  static Zone FromDegrees(double theta_min_deg, double theta_max_deg);

  double theta_min_rad() const { return theta_min_rad_; }
  double theta_max_rad() const { return theta_max_rad_; }
  // a = cos(theta_max) < b = cos(theta_min): the zone is x = cos(theta) in [a, b].
  double cos_lower() const { return cos_lower_; }
  double cos_upper() const { return cos_upper_; }
  double solid_angle_sr() const { return 2.0 * M_PI * (cos_upper_ - cos_lower_); }
  bool ContainsCosTheta(double cos_theta) const {
    return cos_theta >= cos_lower_ && cos_theta <= cos_upper_;
  }
  // "[9.00, 57.00] deg"
  std::string ToString() const;

  bool operator==(const Zone& o) const {
    return theta_min_rad_ == o.theta_min_rad_ && theta_max_rad_ == o.theta_max_rad_;
  }

 private:
  double theta_min_rad_, theta_max_rad_;
  double cos_lower_, cos_upper_;
};

inline double DegToRad(double deg) { return deg * (M_PI / 180.0); }
inline double RadToDeg(double rad) { return rad * (180.0 / M_PI); }

}  // namespace zbrdf
