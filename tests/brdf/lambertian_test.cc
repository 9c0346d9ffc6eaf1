#include "brdf/lambertian.h"

#include <gtest/gtest.h>

#include <cmath>

#include "basis/error.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Rng;

TEST(LambertianTest, EvaluatesToAlbedoOverPiAboveTheHorizonOnly) {
  const Rgb albedo(0.5, 0.4, 0.3);
  const LambertianBrdf brdf(albedo);
  Rng rng(1);
  for (int n = 0; n < 100; ++n) {
    const Vec3 w_i = testing::RandomUpperDirection(rng), w_o = testing::RandomUpperDirection(rng);
    const Rgb f = brdf.Eval(w_i, w_o);
    EXPECT_DOUBLE_EQ(f.r, 0.5 / M_PI);
    EXPECT_DOUBLE_EQ(f.g, 0.4 / M_PI);
    EXPECT_DOUBLE_EQ(f.b, 0.3 / M_PI);
    EXPECT_EQ(brdf.Eval(Vec3{w_i.x, w_i.y, -w_i.z}, w_o), Rgb());
    EXPECT_EQ(brdf.Eval(w_i, Vec3{w_o.x, w_o.y, -w_o.z}), Rgb());
  }
}

TEST(LambertianTest, AlbedoByQuadratureIsTheParameter) {
  // f cos is a polynomial of degree 1 in cos theta, which Simpson's rule integrates exactly.
  const LambertianBrdf brdf(Rgb(0.18));
  for (double theta_o : {0.0, 0.7, 1.5}) {
    EXPECT_NEAR(testing::DirectionalAlbedo(brdf, SphericalDirection(theta_o, 1.0)), 0.18, 1e-12);
  }
  EXPECT_TRUE(brdf.IsEnergyConserving());
  EXPECT_FALSE(LambertianBrdf(Rgb(0.5, 1.2, 0.5)).IsEnergyConserving());
}

TEST(LambertianTest, IsReciprocal) {
  const LambertianBrdf brdf(Rgb(0.7, 0.2, 0.1));
  EXPECT_TRUE(brdf.IsReciprocal());
  EXPECT_EQ(testing::MaxReciprocityError(brdf, 2), 0.0);
}

TEST(LambertianTest, CosineSamplingMatchesPdf) {
  const LambertianBrdf brdf(Rgb(0.5));
  // A smooth density: the normalization cubature (1e-7 relative per cell) lands within 1e-9
  // (measured 3e-10); 1e-8.
  EXPECT_SAMPLING_MATCHES_PDF(brdf, SphericalDirection(0.4, 0.2), 11, 1e-8);
  EXPECT_SAMPLING_MATCHES_PDF(brdf, SphericalDirection(1.45, 4.0), 12, 1e-8);
}

TEST(LambertianTest, NoSampleForViewsBelowTheHorizon) {
  const LambertianBrdf brdf(Rgb(0.5));
  const Vec3 below{0.0, 0.6, -0.8};
  EXPECT_EQ(brdf.Sample(below, 0.3, 0.4, 0.5).pdf, 0.0);
  EXPECT_EQ(brdf.Pdf(below, Vec3{0, 0, 1}), 0.0);
}

TEST(LambertianTest, RejectsNegativeAndNonFiniteAlbedo) {
  EXPECT_THROW(LambertianBrdf(Rgb(0.1, -0.1, 0.1)), InputError);
  EXPECT_THROW(LambertianBrdf(Rgb(std::nan(""))), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
