#include "calibration/graycard.h"

#include <gtest/gtest.h>

#include "basis/spherical_harmonics.h"
#include "basis/zonal_basis.h"
#include "tests/calibration/calibration_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

TEST(GrayCard, LambertianCoefficientsHaveClosedForms) {
  const Zone zone = Zone::FromDegrees(9.7, 56.5);
  const std::vector<double> z = LambertianZonalCoefficients(zone, 4, 0.18);
  const double a = zone.cos_lower(), b = zone.cos_upper();
  // Z_00 is the constant 1/sqrt(|zone|): rho/pi * Z_00 * pi (b^2 - a^2).
  const double z00 = 1 / std::sqrt(zone.solid_angle_sr());
  EXPECT_NEAR(z[0], 0.18 / M_PI * z00 * M_PI * (b * b - a * a), 1e-15);
  // Z_10 = sqrt(3) z00 t with t = (2x - a - b) / (b - a): rho/pi 2 pi integral Z_10(x) x dx.
  const double c = std::sqrt(3.0) * z00;
  auto integral = [&](double x) {  // antiderivative of t(x) x
    return (2 * x * x * x / 3 - (a + b) * x * x / 2) / (b - a);
  };
  EXPECT_NEAR(z[1], 0.18 / M_PI * 2 * M_PI * c * (integral(b) - integral(a)), 1e-15);
  for (int l = 2; l <= 4; ++l) EXPECT_NEAR(z[l], 0.0, 1e-16) << "cos(theta) is linear in t";
}

// Acceptance: an 18% gray card with sensor noise: after DC matching the l = 1 and l = 2 terms
// within 1% (the thesis: 2% and 10%).
TEST(GrayCard, DeviationsWithinOnePercent) {
  testing::SimulatedCalibrationRig sim;
  const std::string folder = testing::TempFolder("graycard");
  const nlohmann::json report = RunCalibration("graycard", sim.rig, sim.design, sim.Options(folder))["graycard"];
  std::printf("gray card: %s\n", report.dump().c_str());
  EXPECT_LE(report["l1_deviation"].get<double>(), 0.01);
  EXPECT_LE(report["l2_deviation"].get<double>(), 0.01);
  for (double s : report["scale_rgb"]) EXPECT_NEAR(s, 1.0, 0.02) << "the nominal radiometry is right";
  EXPECT_TRUE(std::filesystem::exists(folder + "/graycard.png"));
  EXPECT_TRUE(std::filesystem::exists(folder + "/graycard-session/zonal.exr"));
  const CalibrationData data = LoadCalibration(folder);
  EXPECT_EQ(data.camera_flat_source, "gray card");
  ASSERT_TRUE(data.scale_rgb.has_value());
  std::filesystem::remove_all(folder);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
