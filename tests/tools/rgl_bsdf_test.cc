// RGL .bsdf export, checked with an independent reader of the format written here from its
// description (Dupuy & Jakob 2018; the field layout and semantics Mitsuba 3's `measured` plugin
// and pbrt-v4's MeasuredBxDF use): tensor-file parsing, the shape checks those readers make, the
// inverse of the marginal-conditional warp of the visible normals (computed from scratch per
// query by integrating the bilinear density, not from precomputed CDFs), and the evaluation
//   f_r(w_i, w_o) cos(theta_i) = max(0, rgb(s)) ndf(m) / (4 sigma(w_o)).
#include "tools/rgl_bsdf.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "basis/error.h"
#include "fitting/material_spec.h"
#include "tools/brdf_export.h"
#include "tools/brdf_input.h"
#include "tools_test_util.h"

namespace zbrdf {
namespace {

using testing::ReadFile;
using testing::Rng;
using testing::TempDir;

// ---- an independent reader ----

struct Field {
  int dtype = 0;
  std::vector<uint64_t> shape;
  std::vector<float> f32;
  std::vector<uint8_t> u8;
};

template <typename T>
T Get(const std::string& bytes, size_t* pos) {
  static_assert(std::endian::native == std::endian::little);
  T v;
  std::memcpy(&v, bytes.data() + *pos, sizeof(T));
  *pos += sizeof(T);
  return v;
}

std::map<std::string, Field> ParseTensorFile(const std::string& path) {
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
std::vector<std::pair<int, double>> NodeWeights(const std::vector<float>& nodes, double value) {
  if (nodes.size() == 1) return {{0, 1.0}};
  int i = 0;
  while (i + 2 < static_cast<int>(nodes.size()) && nodes[i + 1] <= value) ++i;
  const double t = std::clamp((value - nodes[i]) / (nodes[i + 1] - nodes[i]), 0.0, 1.0);
  return {{i, 1 - t}, {i + 1, t}};
}

double Bilinear(const Grid& g, int slice, double ux, double uy) {
  const double px = std::clamp(ux, 0.0, 1.0) * (g.w - 1), py = std::clamp(uy, 0.0, 1.0) * (g.h - 1);
  const int x = std::min(static_cast<int>(px), g.w - 2),
            y = std::min(static_cast<int>(py), g.h - 2);
  const double s = px - x, t = py - y;
  return (1 - t) * ((1 - s) * g.At(slice, x, y) + s * g.At(slice, x + 1, y)) +
         t * ((1 - s) * g.At(slice, x, y + 1) + s * g.At(slice, x + 1, y + 1));
}

// The inverse of the marginal-conditional warp of a parameter-blended, per-slice normalized
// bilinear density: u_y is the marginal CDF at the point's y, u_x the conditional CDF in x.
std::array<double, 2> InvertWarp(const Grid& g, const std::vector<std::pair<int, double>>& slices,
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

// ---- tests ----

struct Agreement {
  double within_80 = 0;        // mean relative error, pairs uniform with theta <= 80 deg
  double cosine_weighted = 0;  // mean relative error, pairs with density cos(theta_i) cos(theta_o)
  double full_hemisphere = 0;  // mean relative error, pairs uniform on the hemisphere
  double max_reader_difference = 0;  // between the independent reader and RglBrdf
};

// Cosine-weighted direction on the upper hemisphere.
Vec3 RandomCosineDirection(Rng& rng) {
  const double r = std::sqrt(rng.Uniform()), phi = 2 * M_PI * rng.Uniform();
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1 - r * r))};
}

// Mean relative error of the independent reader against the model over random pairs, every
// channel where the model is positive.
Agreement Compare(const std::string& spec, const std::string& file, int pairs) {
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
void ExpectAgreement(const Agreement& a) {
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

TEST(RglExport, GgxThroughIndependentReaderWithin3Percent) {
  TempDir dir("rgl_ggx");
  const std::string spec = "ggx:alpha=0.3,F0=0.95,0.64,0.54";
  ExportOptions options;
  options.format = ExportFormat::kRgl;
  options.out = dir.File("ggx.bsdf");
  options.rgl_variant = ExportOptions::RglVariant::kRgb;
  options.scenes = {"mitsuba"};
  const ExportResult result = ExportBrdf(ResolveBrdfInput(spec), options);
  EXPECT_EQ(result.report["ndf"], "ggx D");
  EXPECT_TRUE(result.report["isotropic"].get<bool>());
  ExpectAgreement(Compare(spec, options.out, 3000));
  // The scene snippet references the file by name.
  const std::string xml = ReadFile(dir.File("ggx.mitsuba.xml"));
  EXPECT_NE(xml.find("<bsdf type=\"measured\""), std::string::npos);
  EXPECT_NE(xml.find("value=\"ggx.bsdf\""), std::string::npos);
}

TEST(RglExport, AnisotropicGgxThroughIndependentReader) {
  TempDir dir("rgl_ggx_aniso");
  const std::string spec = "ggx:alpha_x=0.2,alpha_y=0.45,F0=0.9,kd=0.05";
  ExportOptions options;
  options.format = ExportFormat::kRgl;
  options.out = dir.File("aniso.bsdf");
  options.rgl_variant = ExportOptions::RglVariant::kRgb;
  options.scenes = {};
  const ExportResult result = ExportBrdf(ResolveBrdfInput(spec), options);
  EXPECT_FALSE(result.report["isotropic"].get<bool>());
  ExpectAgreement(Compare(spec, options.out, 1000));
}

TEST(RglExport, SpectralVariantForPbrt) {
  TempDir dir("rgl_spectral");
  const std::string spec = "ggx:alpha=0.3,F0=0.5,kd=0.2";  // gray: flat spectra
  ExportOptions options;
  options.format = ExportFormat::kRgl;
  options.out = dir.File("gray.bsdf");
  const ExportResult result = ExportBrdf(ResolveBrdfInput(spec), options);
  ASSERT_TRUE(std::filesystem::exists(dir.File("gray.spectral.bsdf")));
  const std::string pbrt = ReadFile(dir.File("gray.pbrt"));
  EXPECT_NE(pbrt.find("Material \"measured\" \"string filename\" [ \"gray.spectral.bsdf\" ]"),
            std::string::npos);
  auto fields = ParseTensorFile(dir.File("gray.spectral.bsdf"));
  // pbrt-v4's checks: spectra [phi, theta, n_lambda, S, S] and wavelengths, both float32.
  ASSERT_TRUE(fields.count("spectra") && fields.count("wavelengths"));
  EXPECT_FALSE(fields.count("rgb"));
  const Field& spectra = fields["spectra"];
  ASSERT_EQ(spectra.shape.size(), 5u);
  EXPECT_EQ(spectra.shape[2], fields["wavelengths"].shape[0]);
  EXPECT_EQ(fields["wavelengths"].dtype, 10);
  // A gray material's spectra are flat at every node: the value at 380 nm equals the one at
  // 780 nm (float rounding).
  const size_t n_lambda = spectra.shape[2], slice = spectra.shape[3] * spectra.shape[4];
  for (size_t s = 0; s < spectra.shape[0] * spectra.shape[1]; ++s) {
    for (size_t i = 0; i < slice; i += 17) {
      const float first = spectra.f32[(s * n_lambda) * slice + i];
      const float last = spectra.f32[(s * n_lambda + n_lambda - 1) * slice + i];
      ASSERT_NEAR(first, last, 1e-5 * std::max(1.0f, first));
    }
  }
  EXPECT_EQ(result.report["spectral"]["out_of_gamut_nodes"].get<int64_t>(), 0);
  // The spectral file, reduced back to RGB, gives the same BRDF as the RGB file.
  const auto rgb_file = RglBrdf::FromFile(dir.File("gray.bsdf"));
  const auto spectral_file = RglBrdf::FromFile(dir.File("gray.spectral.bsdf"));
  Rng rng(3);
  for (int k = 0; k < 200; ++k) {
    const Vec3 w_i = testing::RandomUpperDirection(rng), w_o = testing::RandomUpperDirection(rng);
    const Rgb a = rgb_file->Eval(w_i, w_o), b = spectral_file->Eval(w_i, w_o);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(a[c], b[c], 1e-4 * a[c] + 1e-9);
  }
}

TEST(RglBrdf, SamplerDensityIsNormalizedAndMatchesPdf) {
  TempDir dir("rgl_sampling");
  ExportOptions options;
  options.format = ExportFormat::kRgl;
  options.out = dir.File("m.bsdf");
  options.rgl_variant = ExportOptions::RglVariant::kRgb;
  options.scenes = {};
  ExportBrdf(ResolveBrdfInput("ggx:alpha=0.35,F0=0.9"), options);
  const auto brdf = RglBrdf::FromFile(options.out);
  Rng rng(11);
  for (double theta_o : {0.3, 1.0}) {
    const Vec3 w_o = SphericalDirection(theta_o, 0.7);
    // Every sample's density is what Pdf() says.
    for (int k = 0; k < 200; ++k) {
      const BrdfSample s = brdf->Sample(w_o, rng.Uniform(), rng.Uniform(), rng.Uniform());
      if (s.pdf <= 0) continue;
      ASSERT_NEAR(brdf->Pdf(w_o, s.w_i), s.pdf, 1e-6 * s.pdf);
    }
    // Pdf integrates to 1 over the sphere: midpoint rule in (cos theta, phi), 400 x 400 cells.
    // The density is bounded and piecewise smooth, so the rule's error is well under 1%.
    double integral = 0;
    const int n = 400;
    for (int a = 0; a < n; ++a) {
      const double z = -1 + 2 * (a + 0.5) / n;
      for (int b = 0; b < n; ++b) {
        const double phi = 2 * M_PI * (b + 0.5) / n;
        const double r = std::sqrt(1 - z * z);
        integral +=
            brdf->Pdf(w_o, {r * std::cos(phi), r * std::sin(phi), z}) * (2.0 / n) * (2 * M_PI / n);
      }
    }
    EXPECT_NEAR(integral, 1.0, 0.02) << "theta_o " << theta_o;
  }
}

TEST(RglBrdf, MalformedFilesAreReportedByName) {
  TempDir dir("rgl_bad");
  testing::WriteFile(dir.File("bad.bsdf"), "not a tensor file at all");
  try {
    RglBrdf::FromFile(dir.File("bad.bsdf"));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.bsdf"), std::string::npos);
  }
}

}  // namespace
}  // namespace zbrdf
