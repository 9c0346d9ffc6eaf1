#include "brdf/ward.h"

#include <gtest/gtest.h>

#include <cmath>

#include "basis/error.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::Rng;

// Ghosh's thesis eq. 2.8 from spherical angles of the half vector.
double ReferenceWard(double rho_d, double rho_s, double ax, double ay, const Vec3& w_i,
                     const Vec3& w_o) {
  const Vec3 h = Normalize(w_i + w_o);
  const double delta = std::acos(h.z), phi = std::atan2(h.y, h.x);
  const double tan2 = std::tan(delta) * std::tan(delta);
  const double e = tan2 * (std::cos(phi) * std::cos(phi) / (ax * ax) +
                           std::sin(phi) * std::sin(phi) / (ay * ay));
  return rho_d / M_PI + rho_s * std::exp(-e) / (4 * M_PI * ax * ay * std::sqrt(w_i.z * w_o.z));
}

TEST(WardTest, MatchesEquation2_8) {
  const WardBrdf brdf(Rgb(0.1, 0.2, 0.3), Rgb(0.3, 0.2, 0.1), 0.15, 0.4);
  Rng rng(5);
  for (int k = 0; k < 300; ++k) {
    const Vec3 w_i = testing::RandomUpperDirection(rng), w_o = testing::RandomUpperDirection(rng);
    const Rgb f = brdf.Eval(w_i, w_o);
    EXPECT_NEAR(f.r, ReferenceWard(0.1, 0.3, 0.15, 0.4, w_i, w_o), 1e-12 * (1 + f.r));
    EXPECT_NEAR(f.b, ReferenceWard(0.3, 0.1, 0.15, 0.4, w_i, w_o), 1e-12 * (1 + f.b));
  }
}

TEST(WardTest, IsReciprocal) {
  const WardBrdf brdf(Rgb(0.2), Rgb(0.5), 0.1, 0.3);
  EXPECT_TRUE(brdf.IsReciprocal());
  EXPECT_LE(testing::MaxReciprocityError(brdf, 6), 1e-13);
}

TEST(WardTest, AlbedoIsBelowOneAwayFromGrazingButNotAtGrazing) {
  // With rho_s = 1 the specular albedo is below 1 at and near normal incidence for slopes up to
  // 0.5 (quadrature to ~1e-7); at cos(theta_o) = 1e-3 the 1 / sqrt(cos) factor pushes it to
  // 1.36 (alpha = 0.3), which is why IsEnergyConserving() is false.
  for (const auto& [ax, ay] : {std::pair{0.02, 0.02}, {0.1, 0.4}, {0.5, 0.5}}) {
    const WardBrdf brdf(Rgb(0), Rgb(1), ax, ay);
    for (double theta_o : {0.0, 0.6, 1.2}) {
      EXPECT_LE(testing::DirectionalAlbedo(brdf, SphericalDirection(theta_o, 0.7)), 1.0)
          << ax << " " << ay << " " << theta_o;
    }
  }
  const WardBrdf rough(Rgb(0), Rgb(1), 0.3, 0.3);
  EXPECT_GT(testing::DirectionalAlbedo(rough, SphericalDirection(std::acos(1e-3), 0.7)), 1.2);
  EXPECT_FALSE(rough.IsEnergyConserving());
}

TEST(WardTest, SamplingMatchesPdf) {
  EXPECT_SAMPLING_MATCHES_PDF(WardBrdf(Rgb(0.2), Rgb(0.5), 0.1, 0.3), SphericalDirection(0.3, 1.0),
                              31, 1e-4);
  EXPECT_SAMPLING_MATCHES_PDF(WardBrdf(Rgb(0.2), Rgb(0.5), 0.1, 0.3), SphericalDirection(1.2, 2.5),
                              32, 1e-4);
  EXPECT_SAMPLING_MATCHES_PDF(WardBrdf(Rgb(0.0), Rgb(0.5), 0.2, 0.2), SphericalDirection(1.45, 4.0),
                              33, 1e-4);
}

TEST(WardTest, RejectsOutOfRangeParameters) {
  EXPECT_THROW(WardBrdf(Rgb(0.1), Rgb(0.5), 0.0, 0.1), InputError);
  EXPECT_THROW(WardBrdf(Rgb(0.1), Rgb(0.5), 0.1, -0.1), InputError);
  EXPECT_THROW(WardBrdf(Rgb(0.1), Rgb(-0.5), 0.1, 0.1), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
