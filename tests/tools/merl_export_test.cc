// MERL export, read back by an independent implementation of MERL's reference lookup
// (BRDFRead.cpp: half/difference coordinates, square-root theta_h axis, phi_d folded by pi,
// planar channels with the 1/1500, 1.15/1500, 1.66/1500 scales), written here from the
// format's description and sharing no code with the exporter.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
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
using testing::TempDir;

struct MerlFile {
  int dims[3] = {0, 0, 0};
  std::vector<double> values;  // planar R, G, B, as stored
};

MerlFile ReadRaw(const std::string& path) {
  static_assert(std::endian::native == std::endian::little);
  const std::string bytes = ReadFile(path);
  MerlFile file;
  std::memcpy(file.dims, bytes.data(), 12);
  file.values.resize((bytes.size() - 12) / 8);
  std::memcpy(file.values.data(), bytes.data() + 12, file.values.size() * 8);
  return file;
}

// Right-handed rotation about a unit axis (Rodrigues), as MERL's rotate_vector.
Vec3 Rotate(const Vec3& v, const Vec3& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + axis * (Dot(axis, v) * (1 - c)) + Cross(axis, v) * s;
}

// MERL's lookup_brdf_val: the stored value of the bin holding (in, out), times the scales.
Rgb Lookup(const MerlFile& file, const Vec3& in, const Vec3& out, int* bin = nullptr) {
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
void BinCentre(int i, int j, int k, Vec3* in, Vec3* out) {
  const double th = std::pow((i + 0.5) / 90.0, 2) * M_PI / 2;
  const double td = (j + 0.5) / 90.0 * M_PI / 2;
  const double pd = (k + 0.5) / 180.0 * M_PI;
  const Vec3 d{std::sin(td) * std::cos(pd), std::sin(td) * std::sin(pd), std::cos(td)};
  *in = Rotate(d, {0, 1, 0}, th);
  const Vec3 h{std::sin(th), 0, std::cos(th)};
  *out = h * (2 * Dot(*in, h)) - *in;
}

void ExpectMatchesAtBinCentres(const std::string& spec, int stride) {
  TempDir dir("merl_" + std::to_string(std::hash<std::string>()(spec)));
  const BrdfInput input = ResolveBrdfInput(spec);
  ExportOptions options;
  options.format = ExportFormat::kMerl;
  options.out = dir.File("table.binary");
  ExportBrdf(input, options);
  const MerlFile file = ReadRaw(options.out);
  ASSERT_EQ(file.dims[0], 90);
  ASSERT_EQ(file.dims[1], 90);
  ASSERT_EQ(file.dims[2], 180);
  ASSERT_EQ(file.values.size(), 3u * 90 * 90 * 180);
  int checked = 0, nonzero = 0;
  double worst = 0;
  for (int i = 0; i < 90; ++i) {
    for (int j = 0; j < 90; ++j) {
      for (int k = (i + j) % stride; k < 180; k += stride) {
        Vec3 in, out;
        BinCentre(i, j, k, &in, &out);
        int bin = -1;
        const Rgb stored = Lookup(file, in, out, &bin);
        // The independent lookup must find the bin whose centre this is.
        ASSERT_EQ(bin, k + j * 180 + i * 180 * 90) << i << " " << j << " " << k;
        const Rgb expected = (in.z > 0 && out.z > 0) ? input.brdf->Eval(in, out) : Rgb();
        for (int c = 0; c < 3; ++c) {
          // Stored as f / scale in float64 and multiplied back: a few ulps.
          const double error = std::abs(stored[c] - expected[c]);
          worst = std::max(worst, expected[c] > 0 ? error / expected[c] : error);
          ASSERT_LE(error, 1e-6 * std::abs(expected[c]))
              << spec << " bin " << i << " " << j << " " << k;
        }
        ++checked;
        nonzero += expected.Max() > 0;
      }
    }
  }
  EXPECT_GT(nonzero, checked / 3) << "the test must look at bins above the horizon";
  ::testing::Test::RecordProperty("worst_relative_error", std::to_string(worst));
}

TEST(MerlExport, GgxMatchesAtEveryBinCentre) {
  ExpectMatchesAtBinCentres("ggx:alpha=0.25,F0=0.9,0.6,0.3,kd=0.05,0.1,0.2", 1);
}

TEST(MerlExport, BlinnPhongMatchesAtBinCentres) {
  ExpectMatchesAtBinCentres("blinn-phong:kd=0.2,0.3,0.4,ks=0.5,n=80", 7);
}

// A BRDF with a NaN and negative values in a known region, to check that they are reported.
class BrokenBrdf final : public Brdf {
 public:
  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override {
    if (w_i.z <= 0 || w_o.z <= 0) return {};
    if (w_i.z > 0.999 && w_o.z > 0.999) return {std::nan(""), 0.1, 0.1};
    if (w_i.x > 0.5) return {-0.01, 0.1, 0.1};
    return Rgb(0.1);
  }
  bool IsReciprocal() const override { return false; }
  bool IsEnergyConserving() const override { return false; }
  std::string Spec() const override { return "broken"; }
};

TEST(MerlExport, InvalidValuesFailWithCountsAndWriteNothing) {
  TempDir dir("merl_invalid");
  BrdfInput input;
  input.brdf = std::make_shared<BrokenBrdf>();
  input.description = "broken test BRDF";
  ExportOptions options;
  options.format = ExportFormat::kMerl;
  options.out = dir.File("broken.binary");
  try {
    ExportBrdf(input, options);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("NaN"), std::string::npos) << message;
    EXPECT_NE(message.find("negative"), std::string::npos) << message;
    EXPECT_NE(message.find("--clamp-invalid"), std::string::npos) << message;
  }
  EXPECT_FALSE(std::filesystem::exists(options.out));
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));

  options.clamp_invalid = true;
  const ExportResult result = ExportBrdf(input, options);
  EXPECT_GT(result.report["values"]["nan"].get<int64_t>(), 0);
  EXPECT_GT(result.report["values"]["negative"].get<int64_t>(), 0);
  EXPECT_TRUE(result.report["values"]["clamped"].get<bool>());
  const MerlFile file = ReadRaw(options.out);
  for (double v : file.values) ASSERT_TRUE(std::isfinite(v) && v >= 0);
}

TEST(MerlExport, DeltaMaterialIsRefused) {
  TempDir dir("merl_delta");
  ExportOptions options;
  options.format = ExportFormat::kMerl;
  options.out = dir.File("mirror.binary");
  EXPECT_THROW(ExportBrdf(ResolveBrdfInput("mirror:0.9"), options), InputError);
}

}  // namespace
}  // namespace zbrdf
