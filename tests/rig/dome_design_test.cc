#include "rig/dome_design.h"

#include <gtest/gtest.h>

#include <cmath>

#include "basis/error.h"
#include "basis/zone.h"
#include "tests/rig/rig_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

TEST(DomeDesignTest, ThesisPrototypeZoneIsAbout9To57Degrees) {
  const DomeDesign d = DesignDome(LoadRig(testing::SourceRig("thesis.yaml")));
  // Ghosh 2007, section 3.3: the built dome covers 9 to 57 deg off the normal.
  EXPECT_NEAR(RadToDeg(d.zone_min_rad), 9.0, 0.5);
  EXPECT_NEAR(RadToDeg(d.zone_max_rad), 57.0, 0.5);
  // "> 1 pixel/degree measurements over the full measurement zone".
  EXPECT_GT(d.pixels_per_degree_min, 1.0);
  EXPECT_GE(d.pixels_per_degree_mean, d.pixels_per_degree_min);
  EXPECT_NEAR(d.coverage_fraction, std::cos(d.zone_min_rad) - std::cos(d.zone_max_rad), 1e-15);
}

TEST(DomeDesignTest, DesignedDomeCoversNinetyEightPercentOfTheHemisphere) {
  const DomeDesign d = DesignDome(LoadRig(testing::SourceRig("full-dome.yaml")));
  EXPECT_NEAR(RadToDeg(d.zone_max_rad), 90.0, 1e-9);
  EXPECT_GT(d.coverage_fraction, 0.98);
  // The dome of the thesis measures 11" x 11" x 10" (279 x 279 x 254 mm).
  double r_max = 0, z_max = 0;
  for (const auto& p : d.profile) {
    r_max = std::max(r_max, p.r_mm);
    z_max = std::max(z_max, p.z_mm);
  }
  EXPECT_NEAR(2 * r_max, 279, 0.2 * 279);  // our parabola is a guess at theirs: within 20%
  EXPECT_NEAR(z_max, 254, 0.2 * 254);
}

TEST(DomeDesignTest, EveryProfileNormalSendsItsCameraRayToTheSampleCenter) {
  // Independent of the integration: at each profile point, reflecting the ray that arrives from
  // the parabola about the stored normal must aim at the origin. The incoming ray is recomputed
  // here from the camera angle with the paraboloid's closed-form normal.
  const Rig rig = LoadRig(testing::SourceRig("full-dome.yaml"));
  const DomeDesign d = DesignDome(rig);
  const double f = rig.parabola.focal_length_mm, v = rig.parabola.vertex_height_mm;
  const double cz = rig.camera.position_mm.z;
  double worst = 0;
  for (size_t k = 0; k < d.profile.size(); k += 97) {
    const auto& p = d.profile[k];
    const double s = std::sin(p.camera_angle_rad), c = std::cos(p.camera_angle_rad);
    // Camera ray (s t, cz - c t) meets z = v - r^2 / (4 f).
    const double a = s * s / (4 * f), b = -c, q = cz - v;
    const double t = a > 0 ? (-b - std::sqrt(b * b - 4 * a * q)) / (2 * a) : q / c;
    const Vec3 hit{s * t, 0, cz - c * t};
    const Vec3 n = Normalize(Vec3{hit.x / (2 * f), 0, 1});
    const Vec3 reflected = Reflect(Vec3{s, 0, -c}, n);
    const Vec3 dome_normal{p.normal_r, 0, p.normal_z};
    const Vec3 out = Reflect(reflected, dome_normal);
    const Vec3 to_center = Normalize(Vec3{-p.r_mm, 0, -p.z_mm});
    worst = std::max(worst, Length(out - to_center));
  }
  EXPECT_LE(worst, 1e-12);
}

TEST(DomeDesignTest, ImpossibleGeometriesSayWhatToChange) {
  Rig rig = LoadRig(testing::SourceRig("thesis.yaml"));
  rig.parabola.focal_length_mm = 40;  // nearly flat: reflects camera rays back up
  try {
    DesignDome(rig);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("increase parabola.rim_radius_mm or decrease "
                                         "parabola.focal_length_mm"),
              std::string::npos)
        << e.what();
  }
  rig = LoadRig(testing::SourceRig("thesis.yaml"));
  rig.dome.lower_edge_height_mm = 400;
  EXPECT_THROW(DesignDome(rig), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
