// Environment maps: the sampler's density, and the built-in sky's sun.
#include "pictures/environment.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/brdf/brdf_checks.h"

namespace zbrdf {
namespace {

TEST(Environment, SamplingDensityMatchesPdfAndIntegratesToOne) {
  const Environment sky = Environment::Sky();
  testing::Rng rng(3);
  for (int k = 0; k < 2000; ++k) {
    double pdf = 0;
    const Vec3 d = sky.Sample(rng.Uniform(), rng.Uniform(), &pdf);
    ASSERT_NEAR(Length(d), 1.0, 1e-12);
    ASSERT_NEAR(sky.Pdf(d), pdf, 1e-9 * pdf);
  }
  // Integral of the density over the sphere, midpoint rule in (cos theta, phi) on a grid much
  // finer than the map (1024 x 512): the piecewise-constant density is integrated to ~0.1%.
  double integral = 0;
  const int n = 2048;
  for (int a = 0; a < n; ++a) {
    const double y = -1 + 2 * (a + 0.5) / n, r = std::sqrt(1 - y * y);
    for (int b = 0; b < 2 * n; ++b) {
      const double phi = M_PI * (b + 0.5) / n;
      integral += sky.Pdf({r * std::cos(phi), y, r * std::sin(phi)}) * (2.0 / n) * (M_PI / n);
    }
  }
  EXPECT_NEAR(integral, 1.0, 0.005);
  // The sun delivers an irradiance of 2.5 pi at normal incidence (environment.h): integrate the
  // map's luminance over the sun's disk (a cap of 3 deg around its direction) with cos weights.
  const Vec3 sun = sky.sun_direction();
  Vec3 t, b;
  OrthonormalBasis(sun, &t, &b);
  double irradiance = 0, sky_only = 0;
  const int m = 400;
  const double cap = 3.0 * M_PI / 180;
  for (int i = 0; i < m; ++i) {
    const double cos_a = 1 - (1 - std::cos(cap)) * (i + 0.5) / m;
    const double sin_a = std::sqrt(1 - cos_a * cos_a);
    for (int j = 0; j < m; ++j) {
      const double phi = 2 * M_PI * (j + 0.5) / m;
      const Vec3 d = sun * cos_a + t * (sin_a * std::cos(phi)) + b * (sin_a * std::sin(phi));
      const double w = (1 - std::cos(cap)) / m * (2 * M_PI / m) * cos_a;
      irradiance += sky.Radiance(d).Luminance() * w;
      sky_only += 0.8 * w;  // the gradient sky's luminance is below 0.8 there
    }
  }
  EXPECT_NEAR(irradiance, 2.5 * M_PI, 0.02 * 2.5 * M_PI + sky_only);
}

}  // namespace
}  // namespace zbrdf
