// The RGL .bsdf writer and reader (brdf/rgl_bsdf.h), checked with the independent reader of
// tests/brdf/rgl_reader.h. The export command's RGL variants and scene snippets are tested in
// tests/tools/brdf_export_test.cc.
#include "brdf/rgl_bsdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "basis/error.h"
#include "brdf/material_spec.h"
#include "tests/brdf/rgl_reader.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Rng;
using testing::TempDir;

TEST(RglFile, WrittenGgxThroughIndependentReader) {
  TempDir dir("rgl_file_ggx");
  const std::string spec = "ggx:alpha=0.25,F0=0.9,0.7,0.5,kd=0.05";
  const RglExportReport report = WriteRglFile(dir.File("ggx.bsdf"), *MakeBrdf(spec), {});
  EXPECT_EQ(report.ndf_source, "ggx D");
  EXPECT_TRUE(report.isotropic);
  testing::ExpectAgreement(testing::Compare(spec, dir.File("ggx.bsdf"), 1000));
}

// Measured glossy materials (bundled MERL networks; the ndf comes from retro-reflection) at the
// highlight and over the hemisphere, with the default resolutions. Thresholds are issue 18's
// targets (highlight median <= 5%, uniform median <= 3%). Measured here: highlight / uniform
// medians blue-acrylic 0.8% / 0.35%, gold-metallic-paint 0.4% / 1.1%, chrome 0.3% / 0.6%; the
// writer before the sample-space warp followed the change of f_r gave blue-acrylic 6.1% at the
// highlight (docs/formats.md). The medians vary by about 10% of themselves between seeds, far
// inside the margins.
void ExpectTrueAtTheHighlight(const std::string& spec) {
  TempDir dir("rgl_highlight");
  const auto model = MakeBrdf(spec);
  const RglExportReport report = WriteRglFile(dir.File("m.bsdf"), *model, {});
  EXPECT_EQ(report.ndf_source, "retro-reflection (power iteration)");
  const testing::MedianErrors m = testing::CompareMedians(*model, dir.File("m.bsdf"), 300, 600);
  EXPECT_LE(m.peak, 0.05) << spec;
  EXPECT_LE(m.uniform, 0.03) << spec;
  EXPECT_LE(m.cosine, 0.03) << spec;
}

TEST(RglFile, BlueAcrylicTrueAtTheHighlight) { ExpectTrueAtTheHighlight("merl:blue-acrylic"); }

TEST(RglFile, GoldMetallicPaintTrueAtTheHighlight) {
  ExpectTrueAtTheHighlight("merl:gold-metallic-paint");
}

TEST(RglFile, ChromeTrueAtTheHighlight) { ExpectTrueAtTheHighlight("merl:chrome"); }

TEST(RglBrdf, SamplerDensityIsNormalizedAndMatchesPdf) {
  TempDir dir("rgl_sampling");
  const std::string path = dir.File("m.bsdf");
  WriteRglFile(path, *MakeBrdf("ggx:alpha=0.35,F0=0.9"), {});
  const auto brdf = RglBrdf::FromFile(path);
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

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
