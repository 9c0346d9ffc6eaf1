// Acceptance: a Lambertian session on a misaligned rig, captured and processed with the
// calibrated geometry, is within 1.5x the error of a perfectly aligned rig; with the design's
// (uncalibrated) maps it is worse.
#include <filesystem>

#include <gtest/gtest.h>

#include "acquisition/capture_job.h"
#include "acquisition/ground_truth.h"
#include "calibration/calibration_data.h"
#include "tests/calibration/calibration_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

constexpr const char* kMaterial = "lambert:0.18";
constexpr const char* kFaults =
    "misalignment: {projector_offset_mm: [1, 0, 0], camera_tilt_deg: [0.5, 0]}";

// Captures a Lambertian session on the rig as built with the given calibration; returns the
// coefficient error against the material's true coefficients.
double SessionError(const Rig& as_built, const Rig& design, const RigCalibration& calibration,
                    const std::string& dir) {
  VirtualRig::Options o;
  o.seed = 3;
  o.cache_dir = testing::TestCacheDir();
  VirtualRig rig(as_built, MakeBrdf(kMaterial), o);
  CaptureJobOptions job;
  job.out_dir = dir;
  job.order = 4;
  job.pattern_cache_dir = testing::TestCacheDir();
  job.processing.write_hdr_images = false;
  const CaptureJobResult r = RunCaptureJob(design, calibration, rig.camera(), rig.projector(), rig.clock(), job);
  EXPECT_TRUE(r.complete);
  const double error = CoefficientError(r.zonal, TrueZonalCoefficients(*MakeBrdf(kMaterial), r.zonal));
  std::filesystem::remove_all(dir);
  return error;
}

TEST(EndToEnd, CalibratedGeometryRestoresAccuracy) {
  testing::SimulatedCalibrationRig sim(kFaults);
  const std::string folder = testing::TempFolder("e2e-calibration");
  RunCalibration("geometry", sim.rig, sim.design, sim.Options(folder));
  const RigCalibration calibrated = LoadRigCalibration(sim.design, folder, testing::TestCacheDir());

  const double aligned = SessionError(sim.design, sim.design, sim.Nominal(), testing::TempFolder("aligned"));
  const double uncalibrated =
      SessionError(sim.as_built, sim.design, sim.Nominal(), testing::TempFolder("uncalibrated"));
  const double fixed = SessionError(sim.as_built, sim.design, calibrated, testing::TempFolder("calibrated"));
  std::printf("Lambertian 18%%, order 4, fast: aligned rig %.4f, misaligned rig with the design's maps "
              "%.4f, with the calibrated maps %.4f\n",
              aligned, uncalibrated, fixed);
  EXPECT_LE(fixed, 1.5 * aligned);
  EXPECT_GT(uncalibrated, fixed);
  std::filesystem::remove_all(folder);
}

// Every injected fault at once (docs/examples/faults.yaml): misalignment, projector gamma 2.2
// and 30% corner falloff; all four calibration steps.
TEST(EndToEnd, FullCalibrationOfAFaultyRig) {
  testing::SimulatedCalibrationRig sim(std::string(kFaults) +
                                       "\nprojector: {gamma: 2.2, flat_field_falloff: 0.3}");
  const std::string folder = testing::TempFolder("e2e-all");
  const nlohmann::json reports = RunCalibration("all", sim.rig, sim.design, sim.Options(folder));
  EXPECT_EQ(LoadCalibration(folder).Steps().size(), 4u);
  const RigCalibration calibrated = LoadRigCalibration(sim.design, folder, testing::TestCacheDir());
  const double aligned = SessionError(sim.design, sim.design, sim.Nominal(), testing::TempFolder("aligned2"));
  const double fixed = SessionError(sim.as_built, sim.design, calibrated, testing::TempFolder("calibrated2"));
  std::printf("all faults: aligned rig %.4f, calibrated faulty rig %.4f; gray card l1 %.4f l2 %.4f\n",
              aligned, fixed, reports["graycard"]["l1_deviation"].get<double>(),
              reports["graycard"]["l2_deviation"].get<double>());
  EXPECT_LE(fixed, 1.5 * aligned);
  EXPECT_LE(reports["graycard"]["l1_deviation"].get<double>(), 0.01);
  EXPECT_LE(reports["graycard"]["l2_deviation"].get<double>(), 0.01);
  std::filesystem::remove_all(folder);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
