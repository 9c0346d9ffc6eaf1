#include "brdf/blinn_phong.h"

#include <gtest/gtest.h>

#include <cmath>

#include "basis/error.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Rng;

// Independent evaluation from spherical angles: theta_h from the law of cosines on the two
// directions, cos(theta_h) = (cos theta_i + cos theta_o) / |w_i + w_o| with
// |w_i + w_o|^2 = 2 + 2 cos(gamma).
double ReferenceBlinnPhong(double kd, double ks, double n, double theta_i, double phi_i,
                           double theta_o, double phi_o) {
  const double cos_gamma = std::cos(theta_i) * std::cos(theta_o) +
                           std::sin(theta_i) * std::sin(theta_o) * std::cos(phi_i - phi_o);
  const double cos_h = (std::cos(theta_i) + std::cos(theta_o)) / std::sqrt(2 + 2 * cos_gamma);
  return kd / M_PI + ks * (n + 8) / (8 * M_PI) * std::pow(cos_h, n);
}

TEST(BlinnPhongTest, MatchesTheClosedFormFromAngles) {
  const BlinnPhongBrdf brdf(Rgb(0.2, 0.1, 0.05), Rgb(0.5, 0.6, 0.7), 40.0);
  Rng rng(3);
  for (int k = 0; k < 200; ++k) {
    const double ti = 0.5 * M_PI * rng.Uniform(), pi = 2 * M_PI * rng.Uniform();
    const double to = 0.5 * M_PI * rng.Uniform(), po = 2 * M_PI * rng.Uniform();
    const Rgb f = brdf.Eval(SphericalDirection(ti, pi), SphericalDirection(to, po));
    EXPECT_NEAR(f.r, ReferenceBlinnPhong(0.2, 0.5, 40, ti, pi, to, po), 1e-12 * (1 + f.r));
    EXPECT_NEAR(f.b, ReferenceBlinnPhong(0.05, 0.7, 40, ti, pi, to, po), 1e-12 * (1 + f.b));
  }
}

TEST(BlinnPhongTest, NormalIncidenceAlbedoMatchesTheAnalyticNormalization) {
  // At w_o = n: theta_i = 2 theta_h, dw_i = 4 cos(theta_h) dw_h, so the specular albedo is
  // ks (n + 8) [2 (1 - 2^-(n+4)/2) / (n + 4) - (1 - 2^-(n+2)/2) / (n + 2)].
  for (double n : {1.0, 10.0, 100.0}) {
    const BlinnPhongBrdf brdf(Rgb(0), Rgb(1), n);
    const double expected = (n + 8) * (2 * (1 - std::pow(2.0, -(n + 4) / 2)) / (n + 4) -
                                       (1 - std::pow(2.0, -(n + 2) / 2)) / (n + 2));
    // Adaptive Simpson cubature to 1e-7 relative per cell (16 x 32 cells): 1e-6 is safe.
    EXPECT_NEAR(testing::DirectionalAlbedo(brdf, Vec3{0, 0, 1}), expected, 1e-6) << "n=" << n;
  }
  // Hence not energy conserving: with ks = 1 the albedo exceeds 1 (1.018 at n = 100).
  const BlinnPhongBrdf sharp(Rgb(0), Rgb(1), 100.0);
  EXPECT_GT(testing::DirectionalAlbedo(sharp, Vec3{0, 0, 1}), 1.01);
  EXPECT_FALSE(sharp.IsEnergyConserving());
}

TEST(BlinnPhongTest, IsReciprocal) {
  const BlinnPhongBrdf brdf(Rgb(0.3), Rgb(0.6), 25.0);
  EXPECT_TRUE(brdf.IsReciprocal());
  EXPECT_LE(testing::MaxReciprocityError(brdf, 4), 1e-13);
}

TEST(BlinnPhongTest, SamplingMatchesPdf) {
  EXPECT_SAMPLING_MATCHES_PDF(BlinnPhongBrdf(Rgb(0.2), Rgb(0.5), 5.0), SphericalDirection(0.3, 0.5),
                              21, 1e-4);
  EXPECT_SAMPLING_MATCHES_PDF(BlinnPhongBrdf(Rgb(0.2), Rgb(0.5), 100.0),
                              SphericalDirection(1.0, 2.0), 22, 1e-4);
  EXPECT_SAMPLING_MATCHES_PDF(BlinnPhongBrdf(Rgb(0.0), Rgb(0.5), 30.0),
                              SphericalDirection(1.4, 5.0), 23, 1e-4);
}

TEST(BlinnPhongTest, RejectsOutOfRangeParameters) {
  EXPECT_THROW(BlinnPhongBrdf(Rgb(-0.1), Rgb(0.5), 10), InputError);
  EXPECT_THROW(BlinnPhongBrdf(Rgb(0.1), Rgb(0.5), -1), InputError);
  EXPECT_THROW(BlinnPhongBrdf(Rgb(0.1), Rgb(0.5), std::nan("")), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
