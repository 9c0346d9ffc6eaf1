#include "brdf/proxy_sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "brdf/ggx.h"
#include "brdf/lambertian.h"
#include "brdf/nbrdf.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

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
  const HalfVectorProxySampler& proxy() const { return proxy_; }

 private:
  std::unique_ptr<Brdf> brdf_;
  HalfVectorProxySampler proxy_;
};

// Bins about the mirror direction in sin(alpha / 2): the chrome lobe (tens of mrad) spans a few
// of them instead of a sliver of one (cos theta, phi) bin.
testing::SamplingCheckOptions AboutMirror(const Vec3& w_o) {
  testing::SamplingCheckOptions options = testing::ProxyCellsCubature();
  options.bins =
      testing::AxisFrame(Vec3{-w_o.x, -w_o.y, w_o.z}, testing::AxisFrame::Radial::kSinHalfAngle);
  return options;
}

TEST(HalfVectorProxySamplerTest, SamplingMatchesPdfForSharpAndBroadMaterials) {
  // The proxy's density is piecewise constant in theta_h (128 cells) and carries the
  // 1 / (4 |w_o.h|) Jacobian. Over half vectors, on the proxy's own cells, the normalization
  // integral is accurate to a few 1e-9 (measured: |integral - 1| <= 1.9e-9 for all four): 1e-6
  // (it was 1e-3 when the integral was taken about the mirror direction, where the cells' edges
  // cut across the quadrature's) still leaves room for rounding and catches any mass the
  // proxy loses or a wrong factor or exponent (>= 1e-2).
  const auto chrome = NbrdfBrdf::FromName("chrome");
  for (const double theta_o : {0.3, 1.2}) {
    const Vec3 w_o = SphericalDirection(theta_o, 0.4);
    EXPECT_SAMPLING_MATCHES_PDF(*chrome, w_o, 111, 1e-6, AboutMirror(w_o));
  }
  const auto fabric = NbrdfBrdf::FromName("red-fabric");
  EXPECT_SAMPLING_MATCHES_PDF(*fabric, SphericalDirection(0.5, 2.0), 112, 1e-6, testing::ProxyCellsCubature());
  const ProxySampled ggx(std::make_unique<GgxBrdf>(0.1, 0.1, Rgb(0.5), Rgb(0.1)));
  EXPECT_SAMPLING_MATCHES_PDF(ggx, SphericalDirection(0.8, 5.0), 113, 1e-6, testing::ProxyCellsCubature());
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

TEST(HalfVectorProxySamplerTest, IsAGoodProposalForChromeAlsoAtGrazingAngles) {
  // merl:chrome peaks at ~500/sr: cosine sampling's weights spread ~70x their mean near normal
  // incidence; the proxy's stay near 1 (0.3 rad) and within a few times the mean at grazing
  // incidence, where the peak moves off the mirror direction. 20000 samples estimate the
  // spread to within a few percent.
  const auto chrome = NbrdfBrdf::FromName("chrome");
  for (double theta_o : {0.3, 0.9, 1.3}) {
    const Vec3 w_o = SphericalDirection(theta_o, 0.4);
    const double proxy = RelativeSpread(*chrome, w_o, false, 20000);
    const double cosine = RelativeSpread(*chrome, w_o, true, 20000);
    EXPECT_LT(proxy, theta_o < 1 ? 1.5 : 3.0) << theta_o;
    EXPECT_GT(cosine / proxy, 10.0) << theta_o;
  }
}

TEST(HalfVectorProxySamplerTest, LobeFollowsRoughnessAndKeepsACosineFloor) {
  const ProxySampled smooth(std::make_unique<GgxBrdf>(0.05, 0.05, Rgb(0.5), Rgb(0.1)));
  const ProxySampled rough(std::make_unique<GgxBrdf>(0.3, 0.3, Rgb(0.5), Rgb(0.1)));
  // The half-vector density at the normal follows the GGX NDF's peak 1/(pi alpha^2): the
  // smoother lobe is far more concentrated.
  const Vec3 normal{0, 0, 1};
  for (double theta_o : {0.0, 0.5, 1.0}) {
    EXPECT_GT(smooth.proxy().HalfVectorPdf(theta_o, normal),
              10 * rough.proxy().HalfVectorPdf(theta_o, normal));
    for (const ProxySampled* p : {&smooth, &rough}) {
      EXPECT_GE(p->proxy().LobeProbability(SphericalDirection(theta_o, 1.0)), 0.05);
      EXPECT_LE(p->proxy().LobeProbability(SphericalDirection(theta_o, 1.0)), 0.95);
    }
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

TEST(HalfVectorProxySamplerTest, HalfVectorDensityIsItsCellsValueFoundByAcos) {
  // The density finds a half vector's theta_h cell without acos; here the cell is found the
  // plain way (acos, then the first edge above theta_h) and the density read by hand from the
  // table of the probe nearer theta_o, for random half vectors and for ones just either side of
  // every edge (1e-6
  // relative in theta_h: near the normal cos(theta_h) resolves theta_h only to ~1e-8 relative,
  // 1.1e-16 / theta_h^2, so a finer hair would test rounding, not the cell search).
  const ProxySampled ggx(std::make_unique<GgxBrdf>(0.1, 0.1, Rgb(0.5), Rgb(0.1)));
  const HalfVectorProxySampler& proxy = ggx.proxy();
  const std::vector<double>& edges = proxy.theta_edges();
  const int cells = static_cast<int>(edges.size()) - 1;
  auto expected = [&](double theta_o, const Vec3& h) {
    const double theta_h = std::acos(std::clamp(h.z, -1.0, 1.0));
    int cell = static_cast<int>(std::upper_bound(edges.begin(), edges.end(), theta_h) -
                                edges.begin()) - 1;
    cell = std::clamp(cell, 0, cells - 1);
    const double step = proxy.probes()[1].theta_o_rad;
    const int last_pair = static_cast<int>(proxy.probes().size()) - 2;
    const int k = std::min(static_cast<int>(theta_o / step), last_pair);
    const double a = 1 - (theta_o / step - k);
    const auto& nearer = proxy.probes()[a >= 0.5 ? k : k + 1];
    EXPECT_TRUE(nearer.cells != nullptr);  // this GGX has a lobe at every probe
    return nearer.cell_density[cell];
  };
  testing::Rng rng(17);
  std::vector<double> thetas;
  for (int i = 0; i < 4000; ++i) thetas.push_back(0.5 * M_PI * rng.Uniform());
  for (int e = 1; e < cells; ++e) {
    thetas.push_back(edges[e] * (1 + 1e-6));
    thetas.push_back(edges[e] * (1 - 1e-6));
  }
  // theta_o 0.37 and 0.41 rad lie 4.93 and 5.47 probe steps (0.075 rad) up: nearer the probe
  // above and the one below; 1.2 rad is on probe 16 (either rounding of 1.2 / 0.075 picks it).
  for (double theta_o : {0.0, 0.37, 0.41, 1.2}) {
    for (double theta_h : thetas) {
      const Vec3 h = SphericalDirection(theta_h, 1.3);
      ASSERT_DOUBLE_EQ(proxy.HalfVectorPdf(theta_o, h), expected(theta_o, h))
          << "theta_o " << theta_o << " theta_h " << theta_h;
    }
  }
}

TEST(HalfVectorProxySamplerTest, ADiffuseMaterialHasNoLobe) {
  const ProxySampled diffuse(std::make_unique<LambertianBrdf>(Rgb(0.4)));
  EXPECT_EQ(diffuse.proxy().LobeProbability(SphericalDirection(0.4, 1.0)), 0.0);
  const Vec3 w_o = SphericalDirection(0.4, 1.0), w_i = SphericalDirection(0.8, 2.0);
  EXPECT_DOUBLE_EQ(diffuse.Pdf(w_o, w_i), CosineHemispherePdf(w_i));
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
