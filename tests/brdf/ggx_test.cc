#include "brdf/ggx.h"

#include <gtest/gtest.h>

#include <cmath>

#include "basis/error.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Rng;

// Walter et al. 2007 eqs. 33 and 72 in their tangent forms, and Heitz 2014 eq. 99, from angles.
double ReferenceGgx(double ax, double ay, double f0, double kd, const Vec3& w_i, const Vec3& w_o) {
  const Vec3 h = Normalize(w_i + w_o);
  const double theta_h = std::acos(h.z), phi_h = std::atan2(h.y, h.x);
  const double tan2 = std::pow(std::tan(theta_h), 2);
  const double shape = std::pow(std::cos(phi_h) / ax, 2) + std::pow(std::sin(phi_h) / ay, 2);
  const double d =
      1 / (M_PI * ax * ay * std::pow(std::cos(theta_h), 4) * std::pow(1 + tan2 * shape, 2));
  const auto lambda = [&](const Vec3& w) {
    const double theta = std::acos(w.z), phi = std::atan2(w.y, w.x);
    const double alpha2 = std::pow(std::cos(phi) * ax, 2) + std::pow(std::sin(phi) * ay, 2);
    return (-1 + std::sqrt(1 + alpha2 * std::pow(std::tan(theta), 2))) / 2;
  };
  const double g2 = 1 / (1 + lambda(w_i) + lambda(w_o));
  const double fresnel = f0 + (1 - f0) * std::pow(1 - Dot(w_o, h), 5);
  return kd / M_PI + d * g2 * fresnel / (4 * w_i.z * w_o.z);
}

TEST(GgxTest, MatchesTheTangentFormsFromAngles) {
  const GgxBrdf brdf(0.2, 0.45, Rgb(0.04, 0.5, 0.9), Rgb(0.1, 0.2, 0.5));
  Rng rng(9);
  for (int k = 0; k < 300; ++k) {
    const Vec3 w_i = testing::RandomUpperDirection(rng), w_o = testing::RandomUpperDirection(rng);
    const Rgb f = brdf.Eval(w_i, w_o);
    EXPECT_NEAR(f.r, ReferenceGgx(0.2, 0.45, 0.04, 0.1, w_i, w_o), 1e-10 * (1 + f.r));
    EXPECT_NEAR(f.g, ReferenceGgx(0.2, 0.45, 0.5, 0.2, w_i, w_o), 1e-10 * (1 + f.g));
    EXPECT_NEAR(f.b, ReferenceGgx(0.2, 0.45, 0.9, 0.5, w_i, w_o), 1e-10 * (1 + f.b));
  }
}

TEST(GgxTest, DistributionIsNormalizedAndSmithIsConsistentWithIt) {
  // integral D(h) cos(theta_h) dw_h = 1, and the visible projected area
  // integral G1(w_o) max(0, w_o.h) D(h) dw_h = cos(theta_o) (Heitz 2014, eq. 2): an independent
  // check of Lambda against D. Adaptive cubature to 1e-7 relative per cell: 1e-6 is safe.
  for (const auto& [ax, ay] : {std::pair{0.05, 0.05}, {0.1, 0.4}, {0.8, 0.8}}) {
    const GgxBrdf brdf(ax, ay, Rgb(1), Rgb(0));
    EXPECT_NEAR(testing::IntegrateZone([&](const Vec3& h) { return brdf.D(h) * h.z; }, 0, 1), 1.0,
                1e-6)
        << ax << " " << ay;
    for (double theta_o : {0.4, 1.3}) {
      const Vec3 w_o = SphericalDirection(theta_o, 0.6);
      const double g1 = 1 / (1 + brdf.Lambda(w_o));
      const double area = testing::IntegrateZone(
          [&](const Vec3& h) { return g1 * std::max(0.0, Dot(w_o, h)) * brdf.D(h); }, 0, 1);
      EXPECT_NEAR(area, w_o.z, 1e-6) << ax << " " << ay << " " << theta_o;
    }
  }
}

TEST(GgxTest, WhiteFurnace) {
  // F0 = 1, kd = 0: the albedo is the fraction of light not lost to masking-shadowing, at most
  // 1 and close to 1 for smooth surfaces (the height-correlated Smith term loses < 1% at
  // alpha = 0.05 near the normal).
  for (double alpha : {0.05, 0.3, 0.8}) {
    const GgxBrdf brdf(alpha, alpha, Rgb(1), Rgb(0));
    ASSERT_TRUE(brdf.IsEnergyConserving());
    for (double theta_o : {0.0, 1.0, 1.5}) {
      const double albedo = testing::DirectionalAlbedo(brdf, SphericalDirection(theta_o, 0.2));
      EXPECT_LE(albedo, 1.0) << alpha << " " << theta_o;
      if (alpha == 0.05 && theta_o < 1.2) {
        EXPECT_GT(albedo, 0.99) << theta_o;
      }
    }
  }
  EXPECT_FALSE(GgxBrdf(0.3, 0.3, Rgb(0.04), Rgb(0.5)).IsEnergyConserving());
}

TEST(GgxTest, IsReciprocal) {
  const GgxBrdf brdf(0.1, 0.3, Rgb(0.04, 0.5, 0.9), Rgb(0.2));
  EXPECT_TRUE(brdf.IsReciprocal());
  EXPECT_LE(testing::MaxReciprocityError(brdf, 10), 1e-12);
}

TEST(GgxTest, VisibleNormalSamplingMatchesPdf) {
  EXPECT_SAMPLING_MATCHES_PDF(GgxBrdf(0.2, 0.2, Rgb(0.04), Rgb(0.1)), SphericalDirection(0.5, 1.0),
                              51, 1e-4);
  EXPECT_SAMPLING_MATCHES_PDF(GgxBrdf(0.1, 0.4, Rgb(0.5), Rgb(0.2)), SphericalDirection(1.2, 2.0),
                              52, 1e-4);
  EXPECT_SAMPLING_MATCHES_PDF(GgxBrdf(0.05, 0.05, Rgb(0.9), Rgb(0)), SphericalDirection(1.4, 3.5),
                              53, 1e-4);
  EXPECT_SAMPLING_MATCHES_PDF(GgxBrdf(0.5, 0.5, Rgb(0.04), Rgb(0)), Vec3(0, 0, 1), 54, 1e-4);
}

TEST(GgxTest, RejectsOutOfRangeParameters) {
  EXPECT_THROW(GgxBrdf(0.0, 0.1, Rgb(0.04), Rgb(0)), InputError);
  EXPECT_THROW(GgxBrdf(0.1, 0.1, Rgb(1.5), Rgb(0)), InputError);
  EXPECT_THROW(GgxBrdf(0.1, 0.1, Rgb(0.04), Rgb(-0.1)), InputError);
  EXPECT_THROW(GgxBrdf(std::nan(""), 0.1, Rgb(0.04), Rgb(0)), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
