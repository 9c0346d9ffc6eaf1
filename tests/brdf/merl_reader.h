// An independent implementation of MERL's reference lookup (BRDFRead.cpp: half/difference
// coordinates, square-root theta_h axis, phi_d folded by pi, planar channels with the 1/1500,
// 1.15/1500, 1.66/1500 scales), written from the format's description and sharing no code with
// brdf/merl_export.cc or brdf/merl_table.cc. Used by the MERL tests of brdf/ and of the export
// command (tests/tools/brdf_export_test.cc).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "basis/vec3.h"
#include "brdf/brdf.h"
#include "tests/test_files.h"

namespace zbrdf::testing {

struct MerlFile {
  int dims[3] = {0, 0, 0};
  std::vector<double> values;  // planar R, G, B, as stored
};

inline MerlFile ReadRaw(const std::string& path) {
  static_assert(std::endian::native == std::endian::little);
  const std::string bytes = ReadFile(path);
  MerlFile file;
  std::memcpy(file.dims, bytes.data(), 12);
  file.values.resize((bytes.size() - 12) / 8);
  std::memcpy(file.values.data(), bytes.data() + 12, file.values.size() * 8);
  return file;
}

// Right-handed rotation about a unit axis (Rodrigues), as MERL's rotate_vector.
inline Vec3 Rotate(const Vec3& v, const Vec3& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + axis * (Dot(axis, v) * (1 - c)) + Cross(axis, v) * s;
}

// MERL's lookup_brdf_val: the stored value of the bin holding (in, out), times the scales.
inline Rgb Lookup(const MerlFile& file, const Vec3& in, const Vec3& out, int* bin = nullptr) {
  const Vec3 h = Normalize(in + out);
  const double theta_half = std::acos(h.z), phi_half = std::atan2(h.y, h.x);
  const Vec3 diff = Rotate(Rotate(in, {0, 0, 1}, -phi_half), {0, 1, 0}, -theta_half);
  const double theta_diff = std::acos(diff.z);
  double phi_diff = std::atan2(diff.y, diff.x);
  int ih = 0;
  if (theta_half > 0) ih = std::min(89, static_cast<int>(std::sqrt(theta_half / (M_PI / 2)) * 90));
  const int id = std::clamp(static_cast<int>(theta_diff / (M_PI / 2) * 90), 0, 89);
  if (phi_diff < 0) phi_diff += M_PI;
  const int ip = std::clamp(static_cast<int>(phi_diff / M_PI * 180), 0, 179);
  const int index = ip + id * 180 + ih * 180 * 90;
  if (bin) *bin = index;
  const int n = 90 * 90 * 180;
  return {file.values[index] / 1500.0, file.values[index + n] * 1.15 / 1500.0,
          file.values[index + 2 * n] * 1.66 / 1500.0};
}

// The direction pair at the centre of bin (i, j, k): theta_h on the square-root axis.
inline void BinCentre(int i, int j, int k, Vec3* in, Vec3* out) {
  const double th = std::pow((i + 0.5) / 90.0, 2) * M_PI / 2;
  const double td = (j + 0.5) / 90.0 * M_PI / 2;
  const double pd = (k + 0.5) / 180.0 * M_PI;
  const Vec3 d{std::sin(td) * std::cos(pd), std::sin(td) * std::sin(pd), std::cos(td)};
  *in = Rotate(d, {0, 1, 0}, th);
  const Vec3 h{std::sin(th), 0, std::cos(th)};
  *out = h * (2 * Dot(*in, h)) - *in;
}

}  // namespace zbrdf::testing
