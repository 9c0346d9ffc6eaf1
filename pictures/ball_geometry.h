// The material ball's camera, shading frames and per-pixel random numbers, shared by the still
// renderer (material_ball.h) and the relighting samplers (relight.h). Internal to pictures/.
//
// World frame: +y up, +z toward the camera, +x right. The ball is the unit sphere at the origin
// and fills 1 / 1.1 of the frame; the pinhole camera sits 4 units away on +z.
#pragma once

#include <cmath>
#include <cstdint>

#include "basis/vec3.h"
#include "pictures/material_ball.h"

namespace zbrdf::ball {

// SplitMix64 (Steele, Lea & Flood 2014): a small, fast generator, seeded per pixel (and per
// stream, e.g. a frame) so that images do not depend on how rows are split among threads. The
// starting state is a hash of (seed, stream, pixel) through SplitMix64's output function, so that
// nearby seeds give unrelated streams (a state of seed x golden ratio would make seed s + 1's
// stream seed s's shifted by one draw: correlated images).
class PixelRng {
 public:
  PixelRng(uint64_t seed, int x, int y, uint64_t stream = 0)
      : state_(Mix(Mix(Mix(seed) ^ stream) ^
                   (static_cast<uint64_t>(static_cast<uint32_t>(y)) << 32 |
                    static_cast<uint32_t>(x)))) {}
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1p-53; }

 private:
  static uint64_t Mix(uint64_t z) {
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  uint64_t Next() { return Mix(state_ += 0x9E3779B97F4A7C15ull); }
  uint64_t state_;
};

struct Frame {
  Vec3 t, b, n;
  Vec3 ToLocal(const Vec3& d) const { return {Dot(d, t), Dot(d, b), Dot(d, n)}; }
  Vec3 ToWorld(const Vec3& d) const { return FromLocalFrame(d, t, b, n); }
};

// Normal n; tangent along the horizontal circle through the point (material_ball.h).
inline Frame ShadingFrame(const Vec3& n) {
  Frame f;
  f.n = n;
  const Vec3 around = Cross(Vec3{0, 1, 0}, n);
  if (Dot(around, around) > 1e-12) {
    f.t = Normalize(around);
    f.b = Cross(n, f.t);
  } else {
    OrthonormalBasis(n, &f.t, &f.b);
  }
  return f;
}

// What the camera sees through image position (px, py) in pixels (0..size, top left origin).
struct PixelView {
  bool on_ball = false;
  Vec3 direction;  // the camera ray's direction (world; the environment behind when !on_ball)
  Frame frame;     // shading frame at the hit point (on_ball only)
  Vec3 w_o;        // toward the camera, in the shading frame (on_ball only; w_o.z may be <= 0
                   // at the silhouette, where nothing is reflected)
};

inline PixelView ViewThrough(const BallOptions& options, double px, double py) {
  const int size = options.size;
  const double extent = 1.1;
  const double distance = 4.0;
  const double sx = (2.0 * px / size - 1.0) * extent;
  const double sy = (1.0 - 2.0 * py / size) * extent;
  Vec3 origin;
  PixelView view;
  if (options.camera == BallOptions::Camera::kOrthographic) {
    origin = {sx, sy, 10.0};
    view.direction = {0, 0, -1};
  } else {
    const double tan_half = std::tan(std::asin(1.0 / distance)) * extent;
    origin = {0, 0, distance};
    view.direction = Normalize(Vec3{sx / extent * tan_half, sy / extent * tan_half, -1.0});
  }
  // Ray-sphere intersection, |origin + s direction| = 1.
  const double b = Dot(origin, view.direction);
  const double c = Dot(origin, origin) - 1.0;
  const double disc = b * b - c;
  if (disc <= 0) return view;
  view.on_ball = true;
  const Vec3 p = origin + view.direction * (-b - std::sqrt(disc));
  view.frame = ShadingFrame(Normalize(p));
  view.w_o = view.frame.ToLocal(-view.direction);
  return view;
}

}  // namespace zbrdf::ball
