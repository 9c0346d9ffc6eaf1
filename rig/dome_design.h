// Design of the freeform dome by Euler integration of the reflector ODE (docs/design.md section 1;
// Ghosh 2007, section 3.3).
//
// With the parabola, the camera's center of projection and the sample fixed, every camera ray
// reflected by the parabola must be reflected by the dome onto the sample center. The rim
// point D1 is where the ray reflected at the parabola's edge meets the sample plane; at each
// dome point the normal bisects the reversed incoming ray and the direction to the sample
// center; the next camera ray's reflection is intersected with the current tangent plane.
// The design uses the nominal (aligned) geometry: misalignments do not reshape the mirror.
// It runs in the meridional plane (r, z), from the rim toward the axis, far finer than a pixel.
#pragma once

#include <vector>

#include "rig/rig.h"

namespace zbrdf {

struct DomeProfilePoint {
  double r_mm = 0, z_mm = 0;     // point of the profile (r >= 0: distance from the axis)
  double normal_r = 0, normal_z = 0;  // unit normal on the mirror side (toward the sample)
  double camera_angle_rad = 0;   // angle from the axis of the camera chief ray that lands here
  double theta_rad = 0;          // direction from the sample center to this point, from +z
};

struct DomeDesign {
  // Ordered from the rim (lowest point) upward to the top edge; z increases monotonically.
  std::vector<DomeProfilePoint> profile;
  double parabola_shadow_rad = 0;   // directions closer to the normal see the parabola's underside
  double zone_min_rad = 0;          // measured zone from the geometry
  double zone_max_rad = 0;
  double coverage_fraction = 0;     // solid angle of the zone / that of the hemisphere
  double camera_half_angle_rad = 0;  // angle of the ray to the parabola rim at the camera
  double top_hole_radius_mm = 0;    // opening for the camera's view of the parabola
  // Camera pixels per degree of theta along the profile: minimum and mean over the zone.
  double pixels_per_degree_min = 0, pixels_per_degree_mean = 0;
};

// Throws InputError if the geometry cannot work (e.g. the parabola's edge reflects camera rays
// upward, so no dome can return them to the sample), naming the parameters to change.
DomeDesign DesignDome(const Rig& rig);

}  // namespace zbrdf
