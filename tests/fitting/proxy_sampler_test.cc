#include "fitting/proxy_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "brdf_checks.h"
#include "fitting/ggx.h"
#include "fitting/nbrdf.h"

namespace zbrdf {
namespace {

// A BRDF whose Sample/Pdf are the proxy fitted to another BRDF.
class ProxySampled final : public Brdf {
 public:
  explicit ProxySampled(std::unique_ptr<Brdf> brdf) : brdf_(std::move(brdf)), proxy_(*brdf_) {}
  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override { return brdf_->Eval(w_i, w_o); }
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const override {
    return proxy_.Sample(w_o, u_lobe, u0, u1);
  }
  double Pdf(const Vec3& w_o, const Vec3& w_i) const override { return proxy_.Pdf(w_o, w_i); }
  bool IsReciprocal() const override { return brdf_->IsReciprocal(); }
  bool IsEnergyConserving() const override { return brdf_->IsEnergyConserving(); }
  std::string Spec() const override { return "proxy of " + brdf_->Spec(); }
  const LobeProxySampler& proxy() const { return proxy_; }

 private:
  std::unique_ptr<Brdf> brdf_;
  LobeProxySampler proxy_;
};

// Bins about the mirror direction in sin(alpha / 2): the chrome lobe (tens of mrad) spans a few
// of them instead of a sliver of one (cos theta, phi) bin.
testing::SamplingCheckOptions AboutMirror(const Vec3& w_o) {
  testing::SamplingCheckOptions options;
  options.bins =
      testing::AxisFrame(Vec3{-w_o.x, -w_o.y, w_o.z}, testing::AxisFrame::Radial::kSinHalfAngle);
  return options;
}

TEST(LobeProxySamplerTest, SamplingMatchesPdfForSharpAndBroadMaterials) {
  // The proxy's density is smooth (no half-vector singularity): its integral is accurate to the
  // cubature's 1e-7 per cell, so 1e-5 is a safe bound.
  const auto chrome = NbrdfBrdf::FromName("chrome");
  for (const double theta_o : {0.3, 1.2}) {
    const Vec3 w_o = SphericalDirection(theta_o, 0.4);
    EXPECT_SAMPLING_MATCHES_PDF(*chrome, w_o, 111, 1e-5, AboutMirror(w_o));
  }
  const auto fabric = NbrdfBrdf::FromName("red-fabric");
  EXPECT_SAMPLING_MATCHES_PDF(*fabric, SphericalDirection(0.5, 2.0), 112, 1e-5);
  const ProxySampled ggx(std::make_unique<GgxBrdf>(0.1, 0.1, Rgb(0.5), Rgb(0.1)));
  EXPECT_SAMPLING_MATCHES_PDF(ggx, SphericalDirection(0.8, 5.0), 113, 1e-5);
}

// Per-sample relative standard deviation of f cos / pdf (luminance) for w_o, with n samples.
double RelativeSpread(const Brdf& brdf, const Vec3& w_o, bool cosine_only, int n) {
  testing::Rng rng(7);
  double sum = 0, sum2 = 0;
  for (int k = 0; k < n; ++k) {
    const double u = rng.Uniform(), u0 = rng.Uniform(), u1 = rng.Uniform();
    BrdfSample s;
    if (cosine_only) {
      s.w_i = SampleCosineHemisphere(u0, u1);
      s.pdf = CosineHemispherePdf(s.w_i);
    } else {
      s = brdf.Sample(w_o, u, u0, u1);
    }
    const double w =
        s.pdf > 0 && s.w_i.z > 0 ? brdf.Eval(s.w_i, w_o).Luminance() * s.w_i.z / s.pdf : 0.0;
    sum += w;
    sum2 += w * w;
  }
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, sum2 / n - mean * mean)) / mean;
}

TEST(LobeProxySamplerTest, IsAGoodProposalForChrome) {
  // merl:chrome peaks at ~500/sr: cosine sampling's weights spread ~70x their mean, the proxy's
  // under 1.5x (measured 0.7), i.e. thousands of times less variance. 20000 samples estimate
  // the spread to within a few percent for the proxy.
  const auto chrome = NbrdfBrdf::FromName("chrome");
  const Vec3 w_o = SphericalDirection(0.3, 0.4);
  const double proxy = RelativeSpread(*chrome, w_o, false, 20000);
  const double cosine = RelativeSpread(*chrome, w_o, true, 20000);
  EXPECT_LT(proxy, 1.5);
  EXPECT_GT(cosine / proxy, 20.0);
}

TEST(LobeProxySamplerTest, LobeFollowsRoughnessAndKeepsACosineFloor) {
  const ProxySampled smooth(std::make_unique<GgxBrdf>(0.05, 0.05, Rgb(0.5), Rgb(0.1)));
  const ProxySampled rough(std::make_unique<GgxBrdf>(0.3, 0.3, Rgb(0.5), Rgb(0.1)));
  for (double theta_o : {0.0, 0.5, 1.0}) {
    const LobeProxySampler::Mixture a = smooth.proxy().MixtureFor(theta_o);
    const LobeProxySampler::Mixture b = rough.proxy().MixtureFor(theta_o);
    EXPECT_GT(a.exponent[0], 4 * b.exponent[0]) << theta_o;
    EXPECT_GT(a.exponent[1], 4 * b.exponent[1]) << theta_o;
    EXPECT_GE(a.exponent[0], a.exponent[1]);  // the core lobe is the sharper one
  }
  // The cosine part (probability >= 0.05) keeps Pdf positive wherever f cos can be.
  testing::Rng rng(114);
  for (int n = 0; n < 1000; ++n) {
    const Vec3 w_o = testing::RandomUpperDirection(rng), w_i = testing::RandomUpperDirection(rng);
    EXPECT_GE(smooth.Pdf(w_o, w_i), 0.05 * w_i.z / M_PI * (1 - 1e-12));
  }
  EXPECT_EQ(smooth.Sample(Vec3{0, 0.6, -0.8}, 0.5, 0.5, 0.5).pdf, 0.0);
  EXPECT_EQ(smooth.Pdf(Vec3{0, 0.6, -0.8}, Vec3{0, 0, 1}), 0.0);
}

}  // namespace
}  // namespace zbrdf
