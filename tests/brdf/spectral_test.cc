// RGB <-> spectra.
#include "brdf/spectral.h"

#include <gtest/gtest.h>

#include <cmath>

#include "basis/error.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

TEST(Spectral, ObserverFitHasTheCieIntegrals) {
  // The CIE 1931 color matching functions integrate to 106.86 nm each (the tabulated functions
  // at 1 nm; their integrals are equal by the definition of illuminant E's white point). The
  // analytic fit reproduces them to about 1% (Wyman et al. 2013, table 2).
  Vec3 sum;
  for (double lambda = 360.5; lambda < 830; lambda += 1) sum += CieXyz1931(lambda);
  EXPECT_NEAR(sum.x, 106.86, 1.5);
  EXPECT_NEAR(sum.y, 106.86, 1.5);
  EXPECT_NEAR(sum.z, 106.86, 1.5);
  // The peak of y-bar is 1.0 at 555 nm (the fit: within 2%).
  EXPECT_NEAR(CieXyz1931(555).y, 1.0, 0.02);
}

TEST(Spectral, GraysAreFlatAndInGamutColorsRoundTrip) {
  const SpectralBasis basis = SpectralBasis::Default();
  double error = -1;
  const std::vector<double> gray = basis.Upsample(Rgb(0.37), &error);
  for (double v : gray) EXPECT_NEAR(v, 0.37, 1e-12);
  EXPECT_LT(error, 1e-12);
  for (const Rgb& color : {Rgb(0.5, 0.4, 0.3), Rgb(0.2, 0.3, 0.5), Rgb(0.05, 0.06, 0.04)}) {
    const std::vector<double> s = basis.Upsample(color, &error);
    for (double v : s) EXPECT_GE(v, 0.0);
    const Rgb back = basis.Project(s);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[c], color[c], 1e-12);
    EXPECT_LT(error, 1e-12);
  }
  // A saturated primary is outside the gamut of non-negative spectra of this basis: mapped to
  // the nearest representable color, never to negative values, and the change is reported.
  const std::vector<double> red = basis.Upsample(Rgb(1, 0, 0), &error);
  for (double v : red) EXPECT_GE(v, 0.0);
  EXPECT_GT(error, 1e-3);
  const Rgb back = basis.Project(red);
  EXPECT_NEAR(std::max({std::abs(back.r - 1), std::abs(back.g), std::abs(back.b)}), error, 1e-12);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
