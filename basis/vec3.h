// Small fixed-size vector types used across zbrdf.
//
// Vec3 is a 3-D vector in double precision (positions in mm, directions as unit vectors).
// Rgb is a linear-RGB triple (BRDF values in 1/sr, radiances, weights). Both are plain
// aggregates with value semantics; Eigen is used where linear algebra is needed.
#pragma once

#include <algorithm>
#include <cmath>

namespace zbrdf {

struct Vec3 {
  double x = 0, y = 0, z = 0;

  constexpr Vec3() = default;
  constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}

  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
  constexpr Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  constexpr Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  constexpr Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
  constexpr bool operator==(const Vec3&) const = default;
};

constexpr Vec3 operator*(double s, const Vec3& v) { return v * s; }
constexpr double Dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double Length(const Vec3& v) { return std::sqrt(Dot(v, v)); }
inline Vec3 Normalize(const Vec3& v) { return v / Length(v); }

// Mirror reflection of direction d about unit normal n: d - 2 (d.n) n. Works for either sign
// convention of d (incoming or outgoing), as reflection is an involution.
constexpr Vec3 Reflect(const Vec3& d, const Vec3& n) { return d - 2.0 * Dot(d, n) * n; }

// Unit vector from polar angle theta (from +z) and azimuth phi (from +x), radians.
inline Vec3 SphericalDirection(double theta_rad, double phi_rad) {
  const double s = std::sin(theta_rad);
  return {s * std::cos(phi_rad), s * std::sin(phi_rad), std::cos(theta_rad)};
}
inline double SphericalTheta(const Vec3& w) { return std::acos(std::clamp(w.z, -1.0, 1.0)); }
// Azimuth in [0, 2 pi).
inline double SphericalPhi(const Vec3& w) {
  const double p = std::atan2(w.y, w.x);
  return p < 0 ? p + 2 * M_PI : p;
}

// Orthonormal basis (t, b, n) around unit n (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited").
inline void OrthonormalBasis(const Vec3& n, Vec3* t, Vec3* b) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double c = n.x * n.y * a;
  *t = {1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x};
  *b = {c, sign + n.y * n.y * a, -n.y};
}

struct Rgb {
  double r = 0, g = 0, b = 0;

  constexpr Rgb() = default;
  constexpr explicit Rgb(double v) : r(v), g(v), b(v) {}
  constexpr Rgb(double r_, double g_, double b_) : r(r_), g(g_), b(b_) {}

  constexpr double operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
  constexpr double& operator[](int i) { return i == 0 ? r : (i == 1 ? g : b); }
  constexpr Rgb operator+(const Rgb& o) const { return {r + o.r, g + o.g, b + o.b}; }
  constexpr Rgb operator-(const Rgb& o) const { return {r - o.r, g - o.g, b - o.b}; }
  constexpr Rgb operator*(const Rgb& o) const { return {r * o.r, g * o.g, b * o.b}; }
  constexpr Rgb operator*(double s) const { return {r * s, g * s, b * s}; }
  constexpr Rgb operator/(double s) const { return {r / s, g / s, b / s}; }
  constexpr Rgb& operator+=(const Rgb& o) { r += o.r; g += o.g; b += o.b; return *this; }
  constexpr Rgb& operator*=(double s) { r *= s; g *= s; b *= s; return *this; }
  constexpr bool operator==(const Rgb&) const = default;
  constexpr double Max() const { return std::max(r, std::max(g, b)); }
  constexpr double Average() const { return (r + g + b) / 3.0; }
  // Rec. 709 luminance of linear RGB.
  constexpr double Luminance() const { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }
  bool IsFinite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
};

// The colour channels' names in files and messages, in Rgb's order (OpenEXR's names).
inline constexpr const char* kRgbChannelNames[3] = {"R", "G", "B"};

constexpr Rgb operator*(double s, const Rgb& c) { return c * s; }

}  // namespace zbrdf
