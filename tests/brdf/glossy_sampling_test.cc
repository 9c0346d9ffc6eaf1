// The glossy part of each model's sampler (Brdf::SampleGlossy / GlossyPdf), which the rig
// simulator uses as its lobe strategy: a proper density of its own, and with the cosine part
// the full mixture Pdf().
#include <gtest/gtest.h>

#include <memory>

#include "brdf/ashikhmin_shirley.h"
#include "brdf/blinn_phong.h"
#include "brdf/brdf.h"
#include "brdf/ggx.h"
#include "brdf/lambertian.h"
#include "brdf/material_spec.h"
#include "brdf/ward.h"
#include "tests/brdf/brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// Presents a model's glossy part as a Brdf, so that the shared sampling checks apply to it.
class GlossyPart final : public Brdf {
 public:
  explicit GlossyPart(const Brdf& inner) : inner_(inner) {}
  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override { return inner_.Eval(w_i, w_o); }
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const override {
    return inner_.SampleGlossy(w_o, u_lobe, u0, u1);
  }
  double Pdf(const Vec3& w_o, const Vec3& w_i) const override { return inner_.GlossyPdf(w_o, w_i); }
  bool IsReciprocal() const override { return inner_.IsReciprocal(); }
  bool IsEnergyConserving() const override { return inner_.IsEnergyConserving(); }
  std::string Spec() const override { return "glossy part of " + inner_.Spec(); }

 private:
  const Brdf& inner_;
};

TEST(GlossySamplingTest, GlossyPartIsAProperDensityForEachModel) {
  const std::vector<std::string> specs = {
      "ggx:alpha=0.2,F0=0.04,kd=0.3",
      "ggx:alpha_x=0.1,alpha_y=0.3,F0=0.5,kd=0.1",
      "blinn-phong:kd=0.3,ks=0.4,n=60",
      "ward:rho_d=0.2,rho_s=0.1,alpha_x=0.15,alpha_y=0.3",
      "as:rd=0.3,rs=0.2,nu=50,nv=200",
  };
  uint64_t seed = 300;
  for (const std::string& spec : specs) {
    const std::unique_ptr<Brdf> brdf = MakeBrdf(spec);
    const Vec3 w_o = SphericalDirection(0.7, 0.9);
    ASSERT_GT(brdf->GlossyProbability(w_o), 0.0) << spec;
    EXPECT_SAMPLING_MATCHES_PDF(GlossyPart(*brdf), w_o, ++seed, 1e-4);
  }
}

TEST(GlossySamplingTest, MixtureIsGlossyPlusCosine) {
  for (const char* spec : {"ggx:alpha=0.3,F0=0.04,kd=0.5", "merl:blue-acrylic",
                           "ward:rho_d=0.2,rho_s=0.1,alpha=0.2"}) {
    const std::unique_ptr<Brdf> brdf = MakeBrdf(spec);
    testing::Rng rng(17);
    for (int k = 0; k < 200; ++k) {
      const Vec3 w_o = testing::RandomUpperDirection(rng), w_i = testing::RandomUpperDirection(rng);
      const double p = brdf->GlossyProbability(w_o);
      EXPECT_NEAR(brdf->Pdf(w_o, w_i),
                  p * brdf->GlossyPdf(w_o, w_i) + (1 - p) * CosineHemispherePdf(w_i),
                  1e-12 * (1 + brdf->Pdf(w_o, w_i)))
          << spec;
    }
  }
}

TEST(GlossySamplingTest, NetworkGlossyPartSamplesItsProxyLobes) {
  const std::unique_ptr<Brdf> brdf = MakeBrdf("merl:blue-acrylic");
  const Vec3 w_o = SphericalDirection(0.5, 0.0);
  // The proxy's density is piecewise constant in theta_h: 1e-4 per bin suffices (see
  // proxy_sampler_test.cc) and keeps the cubature fast; the normalization is integrated over
  // half vectors on the proxy's cells, to ~1e-9.
  testing::SamplingCheckOptions options = testing::ProxyCellsCubature();
  options.bins = testing::AxisFrame({-w_o.x, -w_o.y, w_o.z}, testing::AxisFrame::Radial::kSinHalfAngle);
  EXPECT_SAMPLING_MATCHES_PDF(GlossyPart(*brdf), w_o, 310, 1e-6, options);
}

// PrepareGlossy / SampleGlossyAt / GlossyPdfAt of the half-vector proxy's models take the
// lobes' density directly; Brdf's own versions derive it from Sample() and the full Pdf(). The
// two must agree: same directions, densities equal up to rounding.
TEST(GlossySamplingTest, PreparedViewOfTheProxyMatchesTheDerivationFromTheMixture) {
  for (const char* spec : {"merl:blue-acrylic", "merl:gold-metallic-paint", "merl:white-fabric"}) {
    const std::unique_ptr<Brdf> brdf = MakeBrdf(spec);
    testing::Rng rng(23);
    int samples = 0;
    for (int k = 0; k < 300; ++k) {
      const Vec3 w_o = testing::RandomUpperDirection(rng);
      const Brdf::GlossyView view = brdf->PrepareGlossy(w_o), base = brdf->Brdf::PrepareGlossy(w_o);
      ASSERT_EQ(view.probability, base.probability) << spec;
      const double u_lobe = rng.Uniform(), u0 = rng.Uniform(), u1 = rng.Uniform();
      const BrdfSample direct = brdf->SampleGlossyAt(view, u_lobe, u0, u1);
      const BrdfSample derived = brdf->Brdf::SampleGlossyAt(base, u_lobe, u0, u1);
      EXPECT_EQ(direct.pdf > 0, derived.pdf > 0) << spec;
      if (!(direct.pdf > 0) || !(derived.pdf > 0)) continue;
      ++samples;
      EXPECT_EQ(direct.w_i.x, derived.w_i.x) << spec;
      EXPECT_EQ(direct.w_i.z, derived.w_i.z) << spec;
      // The derivation subtracts the cosine part from the mixture: relative rounding of order
      // 1e-16 times the ratio of the mixture to the lobe part, which stays below 1e3 here. The
      // direct density is that of the half vector drawn; the derivation finds it again as
      // w_i + w_o normalized, which loses its z to cancellation when w_i lies below the
      // horizon as far as w_o above it (such w_i carry no light; 4 of this test's 900 samples
      // differed there, by up to 2e-9 relative): compared above the horizon.
      if (direct.w_i.z > 0) {
        EXPECT_NEAR(direct.pdf, derived.pdf, 1e-12 * (1 + derived.pdf)) << spec;
      }
      const Vec3 w_i = testing::RandomUpperDirection(rng);
      EXPECT_NEAR(brdf->GlossyPdfAt(view, w_i), brdf->Brdf::GlossyPdfAt(base, w_i),
                  1e-12 * (1 + brdf->Brdf::GlossyPdfAt(base, w_i)))
          << spec;
    }
    EXPECT_GT(samples, 250) << spec;  // the glossy part samples almost every w_o
  }
}

TEST(GlossySamplingTest, LambertianHasNoGlossyPart) {
  const LambertianBrdf brdf(Rgb(0.5));
  const Vec3 w_o = SphericalDirection(0.3, 0.2);
  EXPECT_EQ(brdf.GlossyProbability(w_o), 0.0);
  EXPECT_EQ(brdf.SampleGlossy(w_o, 0.3, 0.4, 0.5).pdf, 0.0);
  EXPECT_EQ(brdf.GlossyPdf(w_o, SphericalDirection(0.2, 1.0)), 0.0);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
