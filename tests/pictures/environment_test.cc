// Environment maps: the sampler's density, and the built-in sky's sun.
#include "pictures/environment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "pictures/image.h"
#include "tests/brdf/brdf_checks.h"
#include "tests/test_files.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

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

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// A small map with distinct, asymmetric values: pixel (x, y) = (x + 1, y + 1, x y + 1) / 8.
// A Radiance RGBE file of `image` (Ward, "Real pixels", Graphics Gems II; Radiance's file
// formats), written here independently of the reader: even scanlines run-length encoded per
// component (runs of 3 or more equal bytes, literals of at most 128), odd ones flat.
std::string RadianceFile(const RgbImage& image) {
  std::string out = "#?RADIANCE\n# test\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n-Y " +
                    std::to_string(image.height) + " +X " + std::to_string(image.width) + "\n";
  for (int y = 0; y < image.height; ++y) {
    std::vector<unsigned char> rgbe(static_cast<size_t>(image.width) * 4);
    for (int x = 0; x < image.width; ++x) {
      const Rgb v = image.At(x, y);
      int e = 0;
      const double scale = v.Max() > 0 ? std::frexp(v.Max(), &e) * 256.0 / v.Max() : 0.0;
      for (int c = 0; c < 3; ++c) rgbe[x * 4 + c] = static_cast<unsigned char>(v[c] * scale);
      rgbe[x * 4 + 3] = v.Max() > 0 ? static_cast<unsigned char>(e + 128) : 0;
    }
    if (y % 2 == 1) {
      out.append(rgbe.begin(), rgbe.end());
      continue;
    }
    out += {2, 2, static_cast<char>(image.width >> 8), static_cast<char>(image.width & 0xff)};
    for (int c = 0; c < 4; ++c) {
      for (int x = 0; x < image.width;) {
        int run = 1;
        while (x + run < image.width && run < 127 && rgbe[(x + run) * 4 + c] == rgbe[x * 4 + c])
          ++run;
        if (run >= 3) {
          out += {static_cast<char>(128 + run), static_cast<char>(rgbe[x * 4 + c])};
          x += run;
          continue;
        }
        const int n = std::min(image.width - x, 128);
        out += static_cast<char>(n);
        for (int k = 0; k < n; ++k) out += static_cast<char>(rgbe[(x + k) * 4 + c]);
        x += n;
      }
    }
  }
  return out;
}

RgbImage Pattern() {
  RgbImage image(16, 8);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 16; ++x) image.At(x, y) = Rgb(x + 1, y + 1, x * y + 1) / 8.0;
  }
  return image;
}

TEST(Environment, RotatedMapTurnsItsRadianceAboutTheVerticalAxis) {
  // Rotating by r and looking along R_y(r) d sees what the original shows along d.
  const Environment env(Pattern());
  testing::Rng rng(5);
  for (double r : {0.3, -1.2, 2.0 * M_PI / 16}) {
    const Environment turned = env.Rotated(r);
    EXPECT_NEAR(turned.rotation_rad(), r, 1e-15);
    for (int k = 0; k < 200; ++k) {
      const Vec3 d = testing::RandomUpperDirection(rng);
      // Direction() convention: (x, z) = sin(theta) (sin phi, -cos phi), phi -> phi + r.
      const double c = std::cos(r), s = std::sin(r);
      const Vec3 rd{d.x * c - d.z * s, d.y, d.z * c + d.x * s};
      ASSERT_EQ(turned.Radiance(rd), env.Radiance(d)) << k;
      ASSERT_NEAR(turned.Pdf(rd), env.Pdf(d), 1e-12 * env.Pdf(d)) << k;
    }
  }
  // The sky's sun turns with it.
  const Environment sky = Environment::Sky();
  const Environment turned = sky.Rotated(0.7);
  const Vec3 sun = turned.sun_direction();
  EXPECT_GT(turned.Radiance(sun).Max(), 50.0);
  EXPECT_NEAR(Length(sun), 1.0, 1e-12);
}

TEST(Environment, TurnSinceAnEarlierCopyCarriesDirectionsWithTheLight) {
  // TurnAboutY against directions of known longitude: phi = atan2(x, -z) grows by the turn.
  const Vec3 ahead{0, 0, -1};  // phi = 0
  const Vec3 quarter = TurnAboutY(M_PI / 2).Forward(ahead);
  EXPECT_NEAR(quarter.x, 1.0, 1e-15);
  EXPECT_NEAR(quarter.z, 0.0, 1e-15);
  const Vec3 tilted = Normalize(Vec3{0.3, 0.5, -0.8});
  const Vec3 turned_tilted = TurnAboutY(0.4).Forward(tilted);
  EXPECT_NEAR(std::atan2(turned_tilted.x, -turned_tilted.z), std::atan2(0.3, 0.8) + 0.4, 1e-14);
  EXPECT_EQ(turned_tilted.y, tilted.y);
  EXPECT_NEAR(Length(turned_tilted), 1.0, 1e-15);

  const Environment env(Pattern());
  const Environment earlier = env.Rotated(0.25);
  const Environment later = earlier.Rotated(-0.9).Rotated(0.2);
  ASSERT_TRUE(later.TurnSince(earlier).has_value());
  const double turn = *later.TurnSince(earlier);
  EXPECT_NEAR(turn, -0.7, 1e-15);
  testing::Rng rng(11);
  for (int k = 0; k < 200; ++k) {
    const Vec3 d = testing::RandomUpperDirection(rng);
    ASSERT_EQ(later.Radiance(TurnAboutY(turn).Forward(d)), earlier.Radiance(d)) << k;
    const Vec3 back = TurnAboutY(turn).Back(TurnAboutY(turn).Forward(d));
    ASSERT_NEAR(Length(back - d), 0.0, 1e-15) << k;
  }
  EXPECT_EQ(*env.TurnSince(env), 0.0);
  // Two maps built from equal images are not copies of one another: no turn is claimed.
  EXPECT_FALSE(Environment(Pattern()).TurnSince(env).has_value());
}

TEST(Environment, MeanRadianceIsTheSolidAngleMeanOfTheLargestChannel) {
  EXPECT_NEAR(Environment::Constant(Rgb(0.2, 0.7, 0.4)).mean_max_radiance(), 0.7, 1e-14);
  // Only the top row lit (value 1, height 4): a cap down to 45 deg, solid angle
  // 2 pi (1 - cos 45 deg) of the sphere's 4 pi.
  RgbImage top(8, 4);
  for (int x = 0; x < 8; ++x) top.At(x, 0) = Rgb(1.0);
  const double expected = (1 - std::cos(M_PI / 4)) / 2;
  EXPECT_NEAR(Environment(std::move(top)).mean_max_radiance(), expected, 1e-12);
}

TEST(Environment, ReadsRadianceHdrAndOpenExrMapsByExtension) {
  testing::TempDir dir("environment-files");
  const RgbImage pattern = Pattern();
  WriteExrImage(dir.File("map.exr"), pattern);
  // Radiance RGBE written by RadianceFile below: the pattern's values (k / 8, under 16) are
  // exact in RGBE (mantissas of 8 bits times 2^(e - 8), e <= 4), so both readers give them back
  // to rounding.
  WriteFileAtomically(dir.File("map.HDR"), RadianceFile(pattern));
  const Environment exr = Environment::FromFile(dir.File("map.exr"));
  const Environment hdr = Environment::FromFile(dir.File("map.HDR"));
  ASSERT_EQ(hdr.image().width, 16);
  ASSERT_EQ(hdr.image().height, 8);
  for (size_t i = 0; i < pattern.pixels.size(); ++i) {
    const Rgb& want = pattern.pixels[i];
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(exr.image().pixels[i][c], want[c], 1e-6);
      EXPECT_NEAR(hdr.image().pixels[i][c], want[c], 1e-12) << i << " " << c;
    }
  }
  // Errors name the file and what to give.
  WriteFileAtomically(dir.File("map.png"), "not an image");
  try {
    Environment::FromFile(dir.File("map.png"));
    ADD_FAILURE() << "a .png map was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(".hdr"), std::string::npos) << e.what();
  }
  WriteFileAtomically(dir.File("broken.hdr"), "#?RADIANCE\ngarbage");
  EXPECT_THROW(Environment::FromFile(dir.File("broken.hdr")), InputError);
  // Cut short, another orientation, XYZE pixels, a damaged run: each an InputError naming the file.
  const std::string good = RadianceFile(pattern);
  std::string rotated = good, xyze = good, damaged = good;
  rotated.replace(rotated.find("-Y 8 +X 16"), 10, "+X 16 -Y 8");
  xyze.replace(xyze.find("rgbe"), 4, "xyze");
  damaged[damaged.find("+X 16\n") + 6 + 4] = static_cast<char>(200);  // a run past the row's end
  for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::string>>{
           {"cut.hdr", good.substr(0, good.size() - 10)},
           {"rotated.hdr", rotated},
           {"xyze.hdr", xyze},
           {"damaged.hdr", damaged}}) {
    WriteFileAtomically(dir.File(name), bytes);
    try {
      Environment::FromFile(dir.File(name));
      ADD_FAILURE() << name << " was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(Environment::FromFile(dir.File("missing.hdr")), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
