// Material-ball previews: a unit sphere with the BRDF, seen by an orthographic or pinhole camera,
// under a directional light or an environment map (docs/preview.md).
//
// World frame: +y up, +z toward the camera, +x right (environment.h). The sample frame at a
// point of the ball has the normal +z and the tangent +x along the horizontal circle through the
// point (the ball's "latitude"), so an anisotropic material's x axis runs around the ball.
//
// Environment lighting is direct only (the ball cannot see itself: it is convex), estimated per
// pixel with `spp` samples. Sampling strategies:
//   kMis     one BRDF sample (Brdf::Sample: the D-BRDF samples its p(h) table, Ghosh 2007
//            section 3.4.1) and one environment sample (proportional to the map) per sample,
//            combined with the power heuristic, beta = 2 (Veach & Guibas 1995)
//   kBrdf    BRDF samples only        kCosine   cosine-weighted samples only (pbrt's default,
//                                                the left half of the thesis's figure 3.11)
//   kLight   environment samples only
// A directional light has irradiance `light_irradiance` at normal incidence (default pi: a white
// Lambertian surface facing it renders at 1); its pixels need no sampling, only antialiasing.
#pragma once

#include <cstdint>
#include <optional>

#include "brdf/brdf.h"
#include "pictures/environment.h"
#include "pictures/image.h"

namespace zbrdf {

struct BallOptions {
  int size = 256;  // image width and height, pixels
  int spp = 64;    // samples per pixel
  enum class Camera { kOrthographic, kPinhole } camera = Camera::kOrthographic;
  enum class Sampling { kMis, kBrdf, kCosine, kLight } sampling = Sampling::kMis;
  // Directional light mode: direction toward the light (world frame, unit). Unset: environment.
  std::optional<Vec3> light_direction;
  double light_irradiance = M_PI;
  Rgb background{0.02};  // behind the ball in directional-light mode
  uint64_t seed = 1;
  // Jitter a pixel's samples after the first (antialiasing); false: every sample at the pixel
  // centre, as the relighting samplers do (relight.h), so that images compare pixel for pixel.
  bool jitter = true;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct BallImage {
  RgbImage image;                 // linear RGB radiance
  std::vector<uint8_t> coverage;  // per pixel: 1 where the pixel centre sees the ball
};

// Renders in parallel over rows; deterministic for a given seed whatever the thread count.
// env may be null in directional-light mode. Throws InputError for bad options (size < 8,
// spp < 1, environment mode without an environment).
BallImage RenderBall(const Brdf& brdf, const Environment* env, const BallOptions& options);

// Root mean square over the pixels where both images see the ball, per RGB channel averaged.
double BallRmse(const BallImage& a, const BallImage& b);

}  // namespace zbrdf
