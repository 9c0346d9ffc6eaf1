// An independent reader of RGL .bsdf files, written from the format's description (Dupuy &
// Jakob 2018; the field layout and semantics Mitsuba 3's `measured` plugin and pbrt-v4's
// MeasuredBxDF use): tensor-file parsing, the shape checks those readers make, the inverse of the
// marginal-conditional warp of the visible normals (computed from scratch per query by
// integrating the bilinear density, not from precomputed CDFs), and the evaluation
//   f_r(w_i, w_o) cos(theta_i) = max(0, rgb(s)) ndf(m) / (4 sigma(w_o)).
// It shares no code with brdf/rgl_bsdf.cc. Used by the RGL tests of brdf/ and of the export
// command (tests/tools/brdf_export_test.cc).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "brdf/material_spec.h"
#include "brdf/rgl_bsdf.h"
#include "tests/brdf/brdf_checks.h"
#include "tests/test_files.h"

namespace zbrdf::testing {

struct Field {
  int dtype = 0;
  std::vector<uint64_t> shape;
  std::vector<float> f32;
  std::vector<uint8_t> u8;
};

template <typename T>
inline T Get(const std::string& bytes, size_t* pos) {
  static_assert(std::endian::native == std::endian::little);
  T v;
  std::memcpy(&v, bytes.data() + *pos, sizeof(T));
  *pos += sizeof(T);
  return v;
}

inline std::map<std::string, Field> ParseTensorFile(const std::string& path) {
  const std::string bytes = ReadFile(path);
  EXPECT_EQ(bytes.substr(0, 12), std::string("tensor_file\0", 12));
  EXPECT_EQ(bytes[12], 1);
  EXPECT_EQ(bytes[13], 0);
  size_t pos = 14;
  const uint32_t n = Get<uint32_t>(bytes, &pos);
  std::map<std::string, Field> fields;
  for (uint32_t k = 0; k < n; ++k) {
    const uint16_t name_length = Get<uint16_t>(bytes, &pos);
    const std::string name = bytes.substr(pos, name_length);
    pos += name_length;
    const uint16_t rank = Get<uint16_t>(bytes, &pos);
    Field f;
    f.dtype = Get<uint8_t>(bytes, &pos);
    const uint64_t offset = Get<uint64_t>(bytes, &pos);
    uint64_t count = 1;
    for (int r = 0; r < rank; ++r) {
      f.shape.push_back(Get<uint64_t>(bytes, &pos));
      count *= f.shape.back();
    }
    if (f.dtype == 10) {  // float32
      f.f32.resize(count);
      std::memcpy(f.f32.data(), bytes.data() + offset, count * 4);
    } else if (f.dtype == 1) {  // uint8
      f.u8.assign(bytes.begin() + offset, bytes.begin() + offset + count);
    }
    fields[name] = std::move(f);
  }
  return fields;
}

// A grid of node values over [0, 1]^2 per slice; the slices of the parameter nodes.
struct Grid {
  int w = 0, h = 0;
  std::vector<float> values;  // slices * h * w
  double At(int slice, int x, int y) const {
    return values[(static_cast<size_t>(slice) * h + y) * w + x];
  }
};

// Linear interpolation weights over ascending nodes (clamped at the ends).
inline std::vector<std::pair<int, double>> NodeWeights(const std::vector<float>& nodes,
                                                       double value) {
  if (nodes.size() == 1) return {{0, 1.0}};
  int i = 0;
  while (i + 2 < static_cast<int>(nodes.size()) && nodes[i + 1] <= value) ++i;
  const double t = std::clamp((value - nodes[i]) / (nodes[i + 1] - nodes[i]), 0.0, 1.0);
  return {{i, 1 - t}, {i + 1, t}};
}

inline double Bilinear(const Grid& g, int slice, double ux, double uy) {
  const double px = std::clamp(ux, 0.0, 1.0) * (g.w - 1), py = std::clamp(uy, 0.0, 1.0) * (g.h - 1);
  const int x = std::min(static_cast<int>(px), g.w - 2),
            y = std::min(static_cast<int>(py), g.h - 2);
  const double s = px - x, t = py - y;
  return (1 - t) * ((1 - s) * g.At(slice, x, y) + s * g.At(slice, x + 1, y)) +
         t * ((1 - s) * g.At(slice, x, y + 1) + s * g.At(slice, x + 1, y + 1));
}

// The inverse of the marginal-conditional warp of a parameter-blended, per-slice normalized
// bilinear density: u_y is the marginal CDF at the point's y, u_x the conditional CDF in x.
inline std::array<double, 2> InvertWarp(const Grid& g,
                                        const std::vector<std::pair<int, double>>& slices,
                                        double px_unit, double py_unit) {
  const int w = g.w, h = g.h;
  // The blended density at the nodes, each slice scaled to integrate to 1 over [0, 1]^2.
  std::vector<double> d(static_cast<size_t>(w) * h, 0.0);
  for (const auto& [slice, weight] : slices) {
    if (weight == 0) continue;
    double integral = 0;
    for (int y = 0; y + 1 < h; ++y) {
      for (int x = 0; x + 1 < w; ++x) {
        integral += (g.At(slice, x, y) + g.At(slice, x + 1, y) + g.At(slice, x, y + 1) +
                     g.At(slice, x + 1, y + 1)) /
                    4.0 / ((w - 1.0) * (h - 1.0));
      }
    }
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x)
        d[static_cast<size_t>(y) * w + x] += weight * g.At(slice, x, y) / integral;
    }
  }
  auto node = [&](int x, int y) { return d[static_cast<size_t>(y) * w + x]; };
  const double dx = 1.0 / (w - 1), dy = 1.0 / (h - 1);
  // Row integrals over x at each row node (the density is linear in x between nodes).
  std::vector<double> row(h, 0.0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x + 1 < w; ++x) row[y] += 0.5 * (node(x, y) + node(x + 1, y)) * dx;
  }
  const double py = std::clamp(py_unit, 0.0, 1.0) / dy;
  const int cy = std::min(static_cast<int>(py), h - 2);
  const double t = py - cy;
  double cdf_y = 0;
  for (int y = 0; y < cy; ++y) cdf_y += 0.5 * (row[y] + row[y + 1]) * dy;
  cdf_y += (row[cy] * t + 0.5 * (row[cy + 1] - row[cy]) * t * t) * dy;
  // Along x at this y: linear in x between nodes with endpoint values interpolated in y.
  auto at_y = [&](int x) { return (1 - t) * node(x, cy) + t * node(x, cy + 1); };
  const double marginal = (1 - t) * row[cy] + t * row[cy + 1];
  const double px = std::clamp(px_unit, 0.0, 1.0) / dx;
  const int cx = std::min(static_cast<int>(px), w - 2);
  const double s = px - cx;
  double cdf_x = 0;
  for (int x = 0; x < cx; ++x) cdf_x += 0.5 * (at_y(x) + at_y(x + 1)) * dx;
  cdf_x += (at_y(cx) * s + 0.5 * (at_y(cx + 1) - at_y(cx)) * s * s) * dx;
  return {marginal > 0 ? cdf_x / marginal : 0.0, cdf_y};
}

class IndependentReader {
 public:
  explicit IndependentReader(const std::string& path) {
    auto fields = ParseTensorFile(path);
    for (const char* name : {"theta_i", "phi_i", "ndf", "sigma", "vndf", "luminance", "rgb",
                             "jacobian", "description"}) {
      EXPECT_TRUE(fields.count(name)) << "missing field " << name;
    }
    // The RGB variant must not have "wavelengths": Mitsuba 3 takes its presence to mean spectral.
    EXPECT_FALSE(fields.count("wavelengths"));
    theta_ = fields["theta_i"].f32;
    phi_ = fields["phi_i"].f32;
    const Field& vndf = fields["vndf"];
    const Field& lum = fields["luminance"];
    const Field& rgb = fields["rgb"];
    // The shape checks of Mitsuba's measured plugin.
    EXPECT_EQ(vndf.shape.size(), 4u);
    EXPECT_EQ(vndf.shape[0], phi_.size());
    EXPECT_EQ(vndf.shape[1], theta_.size());
    EXPECT_EQ(lum.shape[2], lum.shape[3]);
    EXPECT_EQ(rgb.shape.size(), 5u);
    EXPECT_EQ(rgb.shape[2], 3u);
    EXPECT_EQ(rgb.shape[3], lum.shape[2]);
    EXPECT_EQ(rgb.shape[4], lum.shape[3]);
    EXPECT_EQ(fields["jacobian"].dtype, 1);
    EXPECT_EQ(fields["jacobian"].u8.size(), 1u);
    EXPECT_EQ(fields["jacobian"].u8[0], 1);
    for (const char* name : {"theta_i", "phi_i", "ndf", "sigma", "vndf", "luminance", "rgb"}) {
      EXPECT_EQ(fields[name].dtype, 10) << name << " must be float32";
    }
    isotropic_ = phi_.size() <= 2;
    ndf_ = {static_cast<int>(fields["ndf"].shape[1]), static_cast<int>(fields["ndf"].shape[0]),
            fields["ndf"].f32};
    sigma_ = {static_cast<int>(fields["sigma"].shape[1]),
              static_cast<int>(fields["sigma"].shape[0]), fields["sigma"].f32};
    vndf_ = {static_cast<int>(vndf.shape[3]), static_cast<int>(vndf.shape[2]), vndf.f32};
    rgb_ = {static_cast<int>(rgb.shape[4]), static_cast<int>(rgb.shape[3]), rgb.f32};
  }

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const {
    if (w_i.z <= 0 || w_o.z <= 0) return {};
    const Vec3 m = Normalize(w_i + w_o);
    const double theta_o = std::acos(w_o.z), phi_o = std::atan2(w_o.y, w_o.x);
    const double theta_m = std::acos(m.z), phi_m = std::atan2(m.y, m.x);
    auto theta2u = [](double t) { return std::sqrt(t / (M_PI / 2)); };
    auto phi2u = [](double p) { return (p + M_PI) / (2 * M_PI); };
    double uy = phi2u(isotropic_ ? phi_m - phi_o : phi_m);
    uy -= std::floor(uy);
    const double ux = theta2u(theta_m);
    // Slices of the parameter (phi_o, theta_o), last fastest.
    std::vector<std::pair<int, double>> slices;
    for (const auto& [p, wp] : NodeWeights(phi_, phi_o)) {
      for (const auto& [t, wt] : NodeWeights(theta_, theta_o)) {
        slices.push_back({p * static_cast<int>(theta_.size()) + t, wp * wt});
      }
    }
    const auto [sx, sy] = InvertWarp(vndf_, slices, ux, uy);
    Rgb value;
    for (int c = 0; c < 3; ++c) {
      double v = 0;
      for (const auto& [slice, weight] : slices)
        v += weight * Bilinear(rgb_, slice * 3 + c, sx, sy);
      value[c] = std::max(0.0, v);
    }
    const double ndf = Bilinear(ndf_, 0, ux, uy);
    const double sigma = Bilinear(sigma_, 0, theta2u(theta_o), phi2u(phi_o));
    return value * (ndf / (4 * sigma) / w_i.z);
  }

 private:
  std::vector<float> theta_, phi_;
  bool isotropic_ = true;
  Grid ndf_, sigma_, vndf_, rgb_;
};

struct Agreement {
  double within_80 = 0;        // mean relative error, pairs uniform with theta <= 80 deg
  double cosine_weighted = 0;  // mean relative error, pairs with density cos(theta_i) cos(theta_o)
  double full_hemisphere = 0;  // mean relative error, pairs uniform on the hemisphere
  double max_reader_difference = 0;  // between the independent reader and RglBrdf
};

// Cosine-weighted direction on the upper hemisphere.
inline Vec3 RandomCosineDirection(Rng& rng) {
  const double r = std::sqrt(rng.Uniform()), phi = 2 * M_PI * rng.Uniform();
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1 - r * r))};
}

// Mean relative error of the independent reader against the model over random pairs, every
// channel where the model is positive.
inline Agreement Compare(const std::string& spec, const std::string& file, int pairs) {
  const auto model = MakeBrdf(spec);
  const IndependentReader reader(file);
  const auto production = RglBrdf::FromFile(file);
  Rng rng(7);
  Agreement a;
  const double z80 = std::cos(80 * M_PI / 180);
  for (int kind = 0; kind < 3; ++kind) {
    double sum = 0;
    int count = 0;
    for (int k = 0; k < pairs; ++k) {
      Vec3 w_i, w_o;
      if (kind == 0) {
        w_i = testing::RandomUpperDirection(rng, z80);
        w_o = testing::RandomUpperDirection(rng, z80);
      } else if (kind == 1) {
        w_i = RandomCosineDirection(rng);
        w_o = RandomCosineDirection(rng);
      } else {
        w_i = testing::RandomUpperDirection(rng);
        w_o = testing::RandomUpperDirection(rng);
      }
      const Rgb expected = model->Eval(w_i, w_o), got = reader.Eval(w_i, w_o);
      const Rgb other = production->Eval(w_i, w_o);
      for (int c = 0; c < 3; ++c) {
        if (!(expected[c] > 0)) continue;
        sum += std::abs(got[c] - expected[c]) / expected[c];
        ++count;
        a.max_reader_difference = std::max(a.max_reader_difference,
                                           std::abs(other[c] - got[c]) / std::max(got[c], 1e-12));
      }
    }
    (kind == 0 ? a.within_80 : kind == 1 ? a.cosine_weighted : a.full_hemisphere) = sum / count;
  }
  std::printf(
      "%s via .bsdf, mean relative error over %d random pairs: %.4f (theta <= 80 deg), "
      "%.4f (cosine-weighted), %.4f (uniform, whole hemisphere)\n",
      spec.c_str(), pairs, a.within_80, a.cosine_weighted, a.full_hemisphere);
  return a;
}

// The format holds f_r cos(theta_i) on a grid of the lobe's sample space; near the horizon of
// w_i f_r is that value divided by cos(theta_i) -> 0, so a table entry's interpolation error is
// amplified without bound there (docs/formats.md). The 3% criterion applies where the format
// represents f_r (theta <= 80 deg) and to the cosine-weighted average over the whole hemisphere
// (the measure rendering integrates against); the uniform whole-hemisphere figure is reported.
inline void ExpectAgreement(const Agreement& a) {
  EXPECT_LT(a.within_80, 0.03);
  EXPECT_LT(a.cosine_weighted, 0.03);
  // Two readers of one format: they differ only by float rounding of the tables.
  EXPECT_LT(a.max_reader_difference, 1e-4);
  ::testing::Test::RecordProperty("mean_relative_error_within_80deg", std::to_string(a.within_80));
  ::testing::Test::RecordProperty("mean_relative_error_cosine_weighted",
                                  std::to_string(a.cosine_weighted));
  ::testing::Test::RecordProperty("mean_relative_error_full_hemisphere",
                                  std::to_string(a.full_hemisphere));
}

// Median relative errors of the independent reader against the model on three sets of pairs,
// every channel where the model is positive (issue 18: "RGL export true at the peak").
struct MedianErrors {
  double peak = 0;     // highlight pairs (HighlightPair)
  double uniform = 0;  // both directions uniform with theta <= 80 deg
  double cosine = 0;   // both directions with density cos(theta)
};

// A highlight pair: w_o with theta_o uniform in [5, 75] deg and phi_o uniform, and w_i =
// reflect(w_o, h) with h uniform (in solid angle) over the half vectors within 15 deg of the
// normal where Y(f_r) >= Y(f_r(mirror of w_o, w_o)) / 2, i.e. what a viewer sees of the
// highlight; one pair per w_o. Rejection from the 15 deg cap would take ~1e4 draws per pair for
// blue-acrylic (its highlight falls to half within 0.3 deg), so h is drawn from the cap of twice
// the angle at which Y(f_r) first falls below half along 8 azimuths (steps of 15% from 0.02
// deg), at most 15 deg: the same distribution for highlights that are star-shaped about the
// mirror direction and at most twice as wide in another azimuth.
inline std::pair<Vec3, Vec3> HighlightPair(const Brdf& model, Rng& rng) {
  constexpr double kDeg = M_PI / 180;
  for (;;) {
    const Vec3 w_o = SphericalDirection((5 + 70 * rng.Uniform()) * kDeg, 2 * M_PI * rng.Uniform());
    const double half = 0.5 * model.Eval({-w_o.x, -w_o.y, w_o.z}, w_o).Luminance();
    if (!(half > 0)) continue;
    auto f_at = [&](const Vec3& h, Vec3* w_i) {
      *w_i = 2 * Dot(w_o, h) * h - w_o;
      return w_i->z > 0 ? model.Eval(*w_i, w_o).Luminance() : 0.0;
    };
    double width = 0;
    for (int k = 0; k < 8; ++k) {
      double theta = 0.02 * kDeg;
      Vec3 w_i;
      while (theta < 15 * kDeg && f_at(SphericalDirection(theta, k * M_PI / 4), &w_i) >= half) {
        theta *= 1.15;
      }
      width = std::max(width, theta);
    }
    const double cap = std::min(15 * kDeg, 2 * width);
    for (int attempt = 0; attempt < 1000; ++attempt) {
      const double z = 1 - (1 - std::cos(cap)) * rng.Uniform();
      const double r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * M_PI * rng.Uniform();
      Vec3 w_i;
      if (f_at({r * std::cos(phi), r * std::sin(phi), z}, &w_i) >= half) return {w_i, w_o};
    }
  }
}

inline MedianErrors CompareMedians(const Brdf& model, const std::string& file, int peak_pairs,
                                   int pairs) {
  const IndependentReader reader(file);
  Rng rng(18);
  auto median = [&](int kind, int count) {
    std::vector<double> errors;
    const double z80 = std::cos(80 * M_PI / 180);
    for (int k = 0; k < count; ++k) {
      Vec3 w_i, w_o;
      if (kind == 0) {
        std::tie(w_i, w_o) = HighlightPair(model, rng);
      } else if (kind == 1) {
        w_i = RandomUpperDirection(rng, z80);
        w_o = RandomUpperDirection(rng, z80);
      } else {
        w_i = RandomCosineDirection(rng);
        w_o = RandomCosineDirection(rng);
      }
      const Rgb expected = model.Eval(w_i, w_o), got = reader.Eval(w_i, w_o);
      for (int c = 0; c < 3; ++c) {
        if (expected[c] > 0) errors.push_back(std::abs(got[c] - expected[c]) / expected[c]);
      }
    }
    std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
    return errors[errors.size() / 2];
  };
  MedianErrors m;
  m.peak = median(0, peak_pairs);
  m.uniform = median(1, pairs);
  m.cosine = median(2, pairs);
  std::printf(
      "%s via .bsdf, median relative error: %.4f (%d highlight pairs), %.4f (%d pairs, "
      "theta <= 80 deg), %.4f (%d cosine-weighted pairs)\n",
      model.Spec().c_str(), m.peak, peak_pairs, m.uniform, pairs, m.cosine, pairs);
  ::testing::Test::RecordProperty("median_relative_error_highlight", std::to_string(m.peak));
  ::testing::Test::RecordProperty("median_relative_error_within_80deg", std::to_string(m.uniform));
  ::testing::Test::RecordProperty("median_relative_error_cosine_weighted",
                                  std::to_string(m.cosine));
  return m;
}

}  // namespace zbrdf::testing
