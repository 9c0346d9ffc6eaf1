#include "brdf/ashikhmin_shirley.h"

#include <gtest/gtest.h>

#include <cmath>

#include "basis/error.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Rng;

// Ashikhmin & Shirley 2000, eqs. 4-5, from spherical angles of the half vector.
double ReferenceAs(double rd, double rs, double nu, double nv, const Vec3& w_i, const Vec3& w_o) {
  const Vec3 h = Normalize(w_i + w_o);
  const double theta_h = std::acos(h.z), phi_h = std::atan2(h.y, h.x);
  const double exponent = nu * std::pow(std::cos(phi_h), 2) + nv * std::pow(std::sin(phi_h), 2);
  const double kh = Dot(w_i, h);
  const double fresnel = rs + (1 - rs) * std::pow(1 - kh, 5);
  const double specular = std::sqrt((nu + 1) * (nv + 1)) / (8 * M_PI) *
                          std::pow(std::cos(theta_h), exponent) / (kh * std::max(w_i.z, w_o.z)) *
                          fresnel;
  const double diffuse = 28 * rd / (23 * M_PI) * (1 - rs) * (1 - std::pow(1 - w_i.z / 2, 5)) *
                         (1 - std::pow(1 - w_o.z / 2, 5));
  return specular + diffuse;
}

TEST(AshikhminShirleyTest, MatchesThePaper) {
  const AshikhminShirleyBrdf brdf(Rgb(0.4, 0.3, 0.2), Rgb(0.05, 0.1, 0.5), 20.0, 200.0);
  Rng rng(7);
  for (int k = 0; k < 300; ++k) {
    const Vec3 w_i = testing::RandomUpperDirection(rng), w_o = testing::RandomUpperDirection(rng);
    const Rgb f = brdf.Eval(w_i, w_o);
    EXPECT_NEAR(f.r, ReferenceAs(0.4, 0.05, 20, 200, w_i, w_o), 1e-11 * (1 + f.r));
    EXPECT_NEAR(f.b, ReferenceAs(0.2, 0.5, 20, 200, w_i, w_o), 1e-11 * (1 + f.b));
  }
}

TEST(AshikhminShirleyTest, DiffuseAlbedoHasTheClosedForm) {
  // The diffuse term's albedo is Rd (1 - Rs) (1 - (1 - cos theta_o / 2)^5): the 28 / (23 pi)
  // factor normalizes integral (1 - (1 - cos/2)^5) cos dw = 23 pi / 28. The specular part is
  // the same with and without Rd, so the difference isolates it.
  for (double rs : {0.0, 0.4}) {
    const AshikhminShirleyBrdf with(Rgb(1), Rgb(rs), 10, 10), without(Rgb(0), Rgb(rs), 10, 10);
    for (double theta_o : {0.0, 0.9, 1.4}) {
      const Vec3 w_o = SphericalDirection(theta_o, 0.3);
      const double diffuse =
          testing::DirectionalAlbedo(with, w_o) - testing::DirectionalAlbedo(without, w_o);
      EXPECT_NEAR(diffuse, (1 - rs) * (1 - std::pow(1 - w_o.z / 2, 5)), 1e-7)
          << "rs=" << rs << " theta_o=" << theta_o;
    }
  }
}

TEST(AshikhminShirleyTest, AlbedoIsAtMostOneForRdUpToOne) {
  // Worst cases: Rd = 1, over Rs, lobe shapes and views down to cos(theta_o) = 1e-3. The
  // quadrature error (~1e-7) is far below the margin.
  for (double rs : {0.0, 0.5, 1.0}) {
    for (const auto& [nu, nv] : {std::pair{1.0, 1.0}, {10.0, 100.0}, {1000.0, 1000.0}}) {
      const AshikhminShirleyBrdf brdf(Rgb(1), Rgb(rs), nu, nv);
      ASSERT_TRUE(brdf.IsEnergyConserving());
      for (double theta_o : {0.0, 1.0, 1.5, std::acos(1e-3)}) {
        EXPECT_LE(testing::DirectionalAlbedo(brdf, SphericalDirection(theta_o, 0.4)), 1.0)
            << "rs=" << rs << " nu=" << nu << " nv=" << nv << " theta_o=" << theta_o;
      }
    }
  }
  EXPECT_FALSE(AshikhminShirleyBrdf(Rgb(1.1), Rgb(0.1), 1, 1).IsEnergyConserving());
}

TEST(AshikhminShirleyTest, IsReciprocal) {
  const AshikhminShirleyBrdf brdf(Rgb(0.3), Rgb(0.2), 10.0, 300.0);
  EXPECT_TRUE(brdf.IsReciprocal());
  EXPECT_LE(testing::MaxReciprocityError(brdf, 8), 1e-12);
}

TEST(AshikhminShirleyTest, SamplingMatchesPdf) {
  EXPECT_SAMPLING_MATCHES_PDF(AshikhminShirleyBrdf(Rgb(0.3), Rgb(0.2), 10, 100),
                              SphericalDirection(0.3, 0.8), 41, 1e-4);
  EXPECT_SAMPLING_MATCHES_PDF(AshikhminShirleyBrdf(Rgb(0.3), Rgb(0.2), 10, 100),
                              SphericalDirection(1.2, 3.0), 42, 1e-4);
  EXPECT_SAMPLING_MATCHES_PDF(AshikhminShirleyBrdf(Rgb(0.0), Rgb(0.5), 1000, 1000),
                              SphericalDirection(0.6, 5.5), 43, 1e-4);
}

TEST(AshikhminShirleyTest, RejectsOutOfRangeParameters) {
  EXPECT_THROW(AshikhminShirleyBrdf(Rgb(0.1), Rgb(1.5), 1, 1), InputError);
  EXPECT_THROW(AshikhminShirleyBrdf(Rgb(0.1), Rgb(0.5), -1, 1), InputError);
  EXPECT_THROW(AshikhminShirleyBrdf(Rgb(-0.1), Rgb(0.5), 1, 1), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
