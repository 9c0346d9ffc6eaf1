#include "calibration/projector.h"

#include <cmath>

#include <gtest/gtest.h>

#include "acquisition/patterns.h"
#include "calibration/calibration_data.h"
#include "tests/calibration/calibration_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

TEST(MonotoneInterpolate, ExactForLinesAndMonotoneForSteps) {
  const std::vector<int> x = {0, 8, 16, 255};
  const std::vector<double> line = {0, 8 / 255.0, 16 / 255.0, 1};
  const std::vector<double> t = MonotoneInterpolate(x, line);
  ASSERT_EQ(t.size(), 256u);
  for (int i = 0; i < 256; ++i) EXPECT_NEAR(t[i], i / 255.0, 1e-12);
  // A step (flat, jump, flat) must not overshoot or oscillate.
  const std::vector<double> step = MonotoneInterpolate({0, 10, 20, 30}, {0, 0, 1, 1});
  for (size_t i = 1; i < step.size(); ++i) EXPECT_GE(step[i], step[i - 1]);
  EXPECT_GE(*std::min_element(step.begin(), step.end()), 0.0);
  EXPECT_LE(*std::max_element(step.begin(), step.end()), 1.0);
}

// Relative RMS over the zone (projector pixels weighted by their solid angle) of the radiance
// the rig really emits for a pattern set against what the calibration used to make it believes
// it emits, after the best common scale (absolute scale is the gray card's business).
double PatternRadianceError(const RigCalibration& used, const RigCalibration& truth,
                            const CapturePlan& plan, const std::string& cache) {
  const PatternSet set(plan, used, cache);
  double num = 0, den = 0, cross = 0, truth2 = 0;
  std::vector<std::pair<std::vector<double>, std::vector<double>>> per_lobe;
  for (size_t lobe = 1; lobe < plan.lobes.size(); ++lobe) {
    const Pattern p = set.Load(static_cast<int>(lobe));
    for (size_t i = 0; i < p.levels.size(); ++i) {
      if (!truth.ProjectorValid(static_cast<int>(i))) continue;
      const Vec3 w = truth.ProjectorDirection(static_cast<int>(i));
      if (!plan.zone().ContainsCosTheta(w.z)) continue;
      const double omega = truth.projector_solid_angle_sr[i];
      const double believed = used.projector_peak_radiance * used.projector_response[p.levels[i]] *
                              used.projector_flat_field[i];
      const double real = truth.projector_peak_radiance * truth.projector_response[p.levels[i]] *
                          truth.projector_flat_field[i];
      cross += omega * believed * real;
      truth2 += omega * real * real;
      den += omega * believed * believed;
      (void)num;
    }
  }
  // min over k of sum w (k real - believed)^2 = den - cross^2 / truth2.
  return std::sqrt(std::max(0.0, den - cross * cross / truth2) / den);
}

// Acceptance: with projector gamma 2.2 and 30% corner falloff injected, the calibrated
// patterns' radiance is within 1% (RMS over the zone) of what was intended.
TEST(Projector, GammaAndFalloffAreCalibratedToOnePercent) {
  testing::SimulatedCalibrationRig sim("projector: {gamma: 2.2, flat_field_falloff: 0.3}");
  const std::string folder = testing::TempFolder("projector");
  const nlohmann::json report = RunCalibration("projector", sim.rig, sim.design, sim.Options(folder));
  EXPECT_NEAR(report["projector"]["gamma_fit"].get<double>(), 2.2, 0.03);
  const RigCalibration calibrated = LoadRigCalibration(sim.design, folder, testing::TestCacheDir());
  const RigCalibration truth = sim.Truth();
  PlanOptions o;
  o.theta_min_rad = DegToRad(9.7);
  o.theta_max_rad = DegToRad(56.5);
  o.order = 4;
  const CapturePlan plan = MakePlan(o);
  const double calibrated_error = PatternRadianceError(calibrated, truth, plan, folder + "/patterns");
  const double nominal_error = PatternRadianceError(sim.Nominal(), truth, plan, folder + "/patterns");
  std::printf("pattern radiance error: calibrated %.4f, nominal %.4f\n", calibrated_error, nominal_error);
  EXPECT_LT(calibrated_error, 0.01);
  EXPECT_GT(nominal_error, 0.1) << "the injected faults matter";
  std::filesystem::remove_all(folder);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
