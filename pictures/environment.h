// Distant illumination for material previews: an equirectangular (latitude-longitude) HDR map,
// sampled in proportion to its radiance.
//
// World frame of the previews: +y up, +z toward the camera, +x to the right. Map coordinates:
// u = 1/2 + atan2(d.x, -d.z) / (2 pi) across (the map's centre column is what the camera sees
// behind the ball), v = acos(d.y) / pi down (top row = zenith). Radiance is piecewise constant
// per pixel (nearest pixel), which is exactly what the sampler's density describes, so that
// estimates combined by MIS stay unbiased.
//
// Sky(): the built-in procedural environment used when no --envmap is given (docs/preview.md):
// a blue-to-white gradient sky over a dim brown ground, and a sun of 2 deg radius at 40 deg
// elevation, upper left and in front of the ball, delivering an irradiance of 2.5 pi on a
// surface facing it (a white Lambertian surface facing the sun renders at 2.5 from the sun
// alone), rasterized at 1024 x 512 with 4 x 4 supersampling.
//
// Copies are cheap (the image and its tables are shared, immutable).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "basis/vec3.h"
#include "brdf/sampling.h"
#include "pictures/image.h"

namespace zbrdf {

// A turn by turn_rad about +y, the way Environment::Rotated turns a map (counter-clockwise seen
// from above; a direction's phi = atan2(x, -z) grows by turn_rad). A rotation: lengths and solid
// angles are kept.
struct TurnAboutY {
  explicit TurnAboutY(double turn_rad);
  Vec3 Forward(const Vec3& d) const {
    return {d.x * cos_turn - d.z * sin_turn, d.y, d.z * cos_turn + d.x * sin_turn};
  }
  Vec3 Back(const Vec3& d) const {  // the inverse turn
    return {d.x * cos_turn + d.z * sin_turn, d.y, d.z * cos_turn - d.x * sin_turn};
  }
  double cos_turn = 1, sin_turn = 0;
};

class Environment {
 public:
  // rotation_rad turns the map about +y (positive: counter-clockwise seen from above).
  // Throws InputError for an empty image.
  explicit Environment(RgbImage latlong, double rotation_rad = 0.0);

  static Environment Sky();
  // A high-frequency studio map: a dim room lit by two rectangular soft boxes and a small, very
  // bright spot (about 3.4 deg across, radiance ~110), so that glossy lobes show their shape
  // (the image error of docs/accuracy.md; relighting benchmarks).
  static Environment Studio();
  static Environment Constant(const Rgb& radiance);
  // An equirectangular map from an OpenEXR (.exr) or Radiance RGBE (.hdr) file (ReadHdrImage in
  // pictures/image.h). Negative pixels are set to 0 and counted in *negative_pixels.
  // Throws InputError naming the file if it cannot be read or its type is not one of these.
  static Environment FromFile(const std::string& path, double rotation_rad = 0.0,
                              int* negative_pixels = nullptr);

  // The same map turned by rotation_rad about +y in addition to this one's rotation. Shares the
  // image and its sampling tables (no copy): a turntable's frames cost nothing to make.
  Environment Rotated(double rotation_rad) const;
  double rotation_rad() const { return rotation_rad_; }
  // When this map is `earlier` turned about +y (both Rotated copies of one map), the turn
  // rotation_rad() - earlier.rotation_rad(): then Radiance(TurnAboutY(turn).Forward(d)) equals
  // earlier.Radiance(d) for every d, which lets a sampler carry a direction with the light
  // (pictures/relight.h, kSmc). nullopt for maps that are not copies of one another.
  std::optional<double> TurnSince(const Environment& earlier) const;

  // Radiance arriving from direction d (unit, world frame; d points away from the ball).
  Rgb Radiance(const Vec3& d) const;
  // A direction with solid-angle density *pdf proportional to the map's largest channel; pdf 0
  // (and any direction) for an all-black map.
  Vec3 Sample(double u0, double u1, double* pdf) const;
  double Pdf(const Vec3& d) const;

  const RgbImage& image() const { return data_->image; }
  // The mean over the sphere of the largest channel's radiance, each pixel weighted by its exact
  // solid angle.
  double mean_max_radiance() const { return data_->mean_max_radiance; }
  // The sun's direction for Sky() (world frame), else zero.
  const Vec3& sun_direction() const { return sun_; }

 private:
  void MapCoordinates(const Vec3& d, double* u, double* v) const;
  Vec3 Direction(double u, double v) const;

  struct Data {
    RgbImage image;
    std::unique_ptr<Distribution2D> distribution;  // null for an all-black map
    double mean_max_radiance = 0;
  };
  std::shared_ptr<const Data> data_;  // shared by rotated copies
  double rotation_rad_ = 0;
  Vec3 sun_;
};

}  // namespace zbrdf
