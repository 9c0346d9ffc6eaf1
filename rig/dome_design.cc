#include "rig/dome_design.h"

#include <cmath>
#include <cstdio>

#include "basis/error.h"
#include "basis/zone.h"

namespace zbrdf {

namespace {

struct Vec2 {
  double r, z;
};

// Camera chief ray at angle alpha from the downward axis, from (0, camera_z), meets the
// parabola z = v - r^2/(4f): returns the hit point and the reflected direction.
bool ReflectOffParabola(const ParabolaParams& p, double camera_z, double alpha, Vec2* hit,
                        Vec2* reflected) {
  const double s = std::sin(alpha), c = std::cos(alpha);
  // (s t)^2 / (4f) - c t + (camera_z - v) = 0; the smaller root is the first hit.
  const double a = s * s / (4 * p.focal_length_mm), b = -c, k = camera_z - p.vertex_height_mm;
  double t;
  if (a < 1e-300) {
    t = k / c;
  } else {
    const double disc = b * b - 4 * a * k;
    if (disc < 0) return false;
    // Stable form of (-b - sqrt(disc)) / (2a) = 2k / (-b + sqrt(disc)).
    t = 2 * k / (-b + std::sqrt(disc));
  }
  hit->r = t * s;
  hit->z = camera_z - t * c;
  double nr = hit->r / (2 * p.focal_length_mm), nz = 1.0;
  const double len = std::hypot(nr, nz);
  nr /= len;
  nz /= len;
  const double dn = s * nr - c * nz;
  reflected->r = s - 2 * dn * nr;
  reflected->z = -c - 2 * dn * nz;
  return true;
}

Vec2 Normalized(Vec2 v) {
  const double len = std::hypot(v.r, v.z);
  return {v.r / len, v.z / len};
}

}  // namespace

DomeDesign DesignDome(const Rig& rig) {
  const ParabolaParams& p = rig.parabola;
  const double camera_z = rig.camera.position_mm.z;
  const double rim_z = p.vertex_height_mm - p.rim_radius_mm * p.rim_radius_mm / (4 * p.focal_length_mm);
  DomeDesign design;
  design.camera_half_angle_rad = std::atan(p.rim_radius_mm / (camera_z - rim_z));
  design.parabola_shadow_rad = std::atan(p.rim_radius_mm / rim_z);

  Vec2 hit, dir;
  ReflectOffParabola(p, camera_z, design.camera_half_angle_rad, &hit, &dir);
  if (dir.z >= -1e-6) {
    char msg[400];
    std::snprintf(msg, sizeof(msg),
                  "dome design: the parabola's edge reflects camera rays %s (slope at the rim "
                  "%.2f); no dome can return them to the sample. Make the rim steeper: increase "
                  "parabola.rim_radius_mm or decrease parabola.focal_length_mm",
                  dir.z > 0 ? "upward" : "horizontally", p.rim_radius_mm / (2 * p.focal_length_mm));
    throw InputError(msg);
  }
  // D1: the edge ray meets the sample plane.
  Vec2 d{hit.r - hit.z / dir.z * dir.r, 0.0};
  const int steps = rig.dome.design_steps;
  const double alpha_max = design.camera_half_angle_rad;
  Vec2 normal{0, 0};
  for (int k = 0; k <= steps; ++k) {
    const double alpha = alpha_max * (1.0 - static_cast<double>(k) / steps);
    if (!ReflectOffParabola(p, camera_z, alpha, &hit, &dir)) break;
    if (k > 0) {
      // Intersect the reflected ray with the tangent plane of the previous point.
      const double denom = dir.r * normal.r + dir.z * normal.z;
      if (std::abs(denom) < 1e-12) break;
      const double t = ((d.r - hit.r) * normal.r + (d.z - hit.z) * normal.z) / denom;
      d = {hit.r + t * dir.r, hit.z + t * dir.z};
    }
    // Normal: bisector of the reversed incoming ray and the direction to the sample center.
    const Vec2 to_sample = Normalized({-d.r, -d.z});
    normal = Normalized({-dir.r + to_sample.r, -dir.z + to_sample.z});
    // Stop where the dome would block the camera's view of the parabola: that is the top hole.
    const double view_cone_r = (camera_z - d.z) * std::tan(alpha_max);
    if (d.r <= view_cone_r) break;
    if (!design.profile.empty() && d.z <= design.profile.back().z_mm) {
      throw NumericalError("dome design: the profile stopped rising at r = " +
                           std::to_string(d.r) + " mm; increase dome.design_steps");
    }
    DomeProfilePoint point;
    point.r_mm = d.r;
    point.z_mm = d.z;
    point.normal_r = normal.r;
    point.normal_z = normal.z;
    point.camera_angle_rad = alpha;
    point.theta_rad = std::atan2(d.r, d.z);
    design.profile.push_back(point);
  }
  if (design.profile.size() < 10) {
    throw InputError("dome design: fewer than 10 profile points; check the camera height and "
                     "the parabola (the dome closes on the camera's view almost at once)");
  }
  design.top_hole_radius_mm = design.profile.back().r_mm;

  // Built domes stop above the sample plane: drop the profile below the lower edge.
  if (rig.dome.lower_edge_height_mm > 0) {
    std::vector<DomeProfilePoint> kept;
    for (const auto& point : design.profile) {
      if (point.z_mm >= rig.dome.lower_edge_height_mm) kept.push_back(point);
    }
    if (kept.size() < 10) {
      throw InputError("dome.lower_edge_height_mm = " +
                       std::to_string(rig.dome.lower_edge_height_mm) +
                       " leaves no dome (its top is at " +
                       std::to_string(design.profile.back().z_mm) + " mm)");
    }
    design.profile = std::move(kept);
  }
  const double theta_top = design.profile.back().theta_rad;
  design.zone_min_rad = std::max(design.parabola_shadow_rad, theta_top);
  design.zone_max_rad = design.profile.front().theta_rad;
  if (design.zone_min_rad >= design.zone_max_rad) {
    throw InputError("dome design: the parabola hides every direction the dome covers (shadow " +
                     std::to_string(RadToDeg(design.parabola_shadow_rad)) +
                     " deg); lower dome.lower_edge_height_mm or shrink the parabola");
  }
  design.coverage_fraction = std::cos(design.zone_min_rad) - std::cos(design.zone_max_rad);

  // Pixels per degree: camera image radius (pixels) per degree of theta along the profile.
  const double image_distance =
      1.0 / (1.0 / rig.camera.focal_length_mm - 1.0 / rig.camera.focus_distance_mm);
  const double pitch_mm = rig.camera.pixel_pitch_um * 1e-3;
  double min_ppd = INFINITY, sum_ppd = 0;
  for (size_t k = 1; k < design.profile.size(); ++k) {
    const auto& a = design.profile[k - 1];
    const auto& b = design.profile[k];
    const double mid = 0.5 * (a.theta_rad + b.theta_rad);
    if (mid < design.zone_min_rad || mid > design.zone_max_rad) continue;
    const double pixels =
        image_distance * std::abs(std::tan(a.camera_angle_rad) - std::tan(b.camera_angle_rad)) /
        pitch_mm;
    const double degrees = std::abs(RadToDeg(a.theta_rad - b.theta_rad));
    if (degrees <= 0) continue;
    const double ppd = pixels / degrees;
    min_ppd = std::min(min_ppd, ppd);
    sum_ppd += ppd * degrees;
  }
  design.pixels_per_degree_min = min_ppd;
  design.pixels_per_degree_mean =
      sum_ppd / RadToDeg(design.zone_max_rad - design.zone_min_rad);
  return design;
}

}  // namespace zbrdf
