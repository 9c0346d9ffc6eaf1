// `zbrdf export` (tools/brdf_export.h) end to end: RGL variants and scene snippets, read back by
// the independent RGL reader of tests/brdf/rgl_reader.h, and the MERL export's refusal of invalid
// values (unless clamped, with counts) and of delta materials, read back by the independent MERL
// lookup of tests/brdf/merl_reader.h.
#include "tools/brdf_export.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>

#include "basis/error.h"
#include "brdf/rgl_bsdf.h"
#include "tests/brdf/merl_reader.h"
#include "tests/brdf/rgl_reader.h"
#include "tools/brdf_input.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Agreement;
using testing::Compare;
using testing::ExpectAgreement;
using testing::Field;
using testing::MerlFile;
using testing::ParseTensorFile;
using testing::ReadFile;
using testing::ReadRaw;
using testing::Rng;
using testing::TempDir;

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

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
