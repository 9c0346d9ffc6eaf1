#include "brdf/retro.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "basis/error.h"
#include "brdf/material_spec.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Rng;

TEST(RetroTest, PeaksTowardTheLightAndMatchesTheClosedFormFromAngles) {
  const RetroBrdf brdf(Rgb(0.1), Rgb(0.6, 0.5, 0.4), 20.0);
  Rng rng(5);
  for (int k = 0; k < 200; ++k) {
    const double ti = 0.5 * M_PI * rng.Uniform(), pi = 2 * M_PI * rng.Uniform();
    const double to = 0.5 * M_PI * rng.Uniform(), po = 2 * M_PI * rng.Uniform();
    // cos of the angle between the directions, by the spherical law of cosines.
    const double cos_g = std::cos(ti) * std::cos(to) + std::sin(ti) * std::sin(to) * std::cos(pi - po);
    const double expected = 0.1 / M_PI + 0.6 * 21.0 / (2 * M_PI) * std::pow(std::max(0.0, cos_g), 20.0);
    const Rgb f = brdf.Eval(SphericalDirection(ti, pi), SphericalDirection(to, po));
    EXPECT_NEAR(f.r, expected, 1e-12 * (1 + expected));
  }
  // Retro, not mirror: back toward w_o it is far brighter than along the mirror direction.
  const Vec3 w_o = SphericalDirection(0.6, 1.0);
  const Vec3 mirror{-w_o.x, -w_o.y, w_o.z};
  EXPECT_GT(brdf.Eval(w_o, w_o).r, 30 * brdf.Eval(mirror, w_o).r);  // 2.04 vs kd / pi
  EXPECT_EQ(brdf.Eval(Vec3{0, 0, -1}, w_o).r, 0.0);
}

TEST(RetroTest, NormalIncidenceAlbedoMatchesTheAnalyticNormalization) {
  // At w_o = n the lobe is cos^n(theta_i): its albedo is (n + 1) / (2 pi) * 2 pi / (n + 2).
  for (double n : {0.0, 5.0, 50.0}) {
    const RetroBrdf brdf(Rgb(0.2), Rgb(0.7), n);
    // Adaptive Simpson cubature to 1e-7 relative per cell: 1e-6 is safe.
    EXPECT_NEAR(testing::DirectionalAlbedo(brdf, Vec3{0, 0, 1}), 0.2 + 0.7 * (n + 1) / (n + 2), 1e-6)
        << "n=" << n;
  }
  EXPECT_TRUE(RetroBrdf(Rgb(0.2), Rgb(0.7), 10).IsEnergyConserving());
  EXPECT_FALSE(RetroBrdf(Rgb(0.5), Rgb(0.7), 10).IsEnergyConserving());
}

TEST(RetroTest, IsReciprocal) {
  const RetroBrdf brdf(Rgb(0.3), Rgb(0.6), 25.0);
  EXPECT_LE(testing::MaxReciprocityError(brdf, 4), 1e-13);
}

TEST(RetroTest, SamplingMatchesPdf) {
  EXPECT_SAMPLING_MATCHES_PDF(RetroBrdf(Rgb(0.2), Rgb(0.5), 10.0), SphericalDirection(0.3, 0.5), 31,
                              1e-4);
  EXPECT_SAMPLING_MATCHES_PDF(RetroBrdf(Rgb(0.0), Rgb(0.5), 60.0), SphericalDirection(1.2, 2.0), 32,
                              1e-4);
}

TEST(RetroTest, SpecRoundTripsAndBadParametersAreRejected) {
  const auto brdf = MakeBrdf("retro:kd=0.1,kr=0.6,n=20");
  EXPECT_EQ(MakeBrdf(brdf->Spec())->Spec(), brdf->Spec());
  const Vec3 w = SphericalDirection(0.4, 0.2);
  EXPECT_DOUBLE_EQ(brdf->Eval(w, w).g, RetroBrdf(Rgb(0.1), Rgb(0.6), 20).Eval(w, w).g);
  EXPECT_THROW(RetroBrdf(Rgb(-0.1), Rgb(0.5), 10), InputError);
  EXPECT_THROW(RetroBrdf(Rgb(0.1), Rgb(0.5), -1), InputError);
  EXPECT_THROW(RetroBrdf(Rgb(0.1), Rgb(0.5), std::numeric_limits<double>::quiet_NaN()), InputError);
  EXPECT_THROW(MakeBrdf("retro:kd=0.1"), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
