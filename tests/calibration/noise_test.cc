#include "calibration/noise.h"

#include <gtest/gtest.h>

#include "basis/error.h"
#include "tests/calibration/calibration_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// Acceptance: gain and read noise within 5% (the fast preset's binned sensor: 40 e-/DN, 40 e-).
TEST(Noise, PhotonTransferRecoversTheSensor) {
  testing::SimulatedCalibrationRig sim;
  const NoiseResult r = CalibrateNoise(sim.rig, sim.Nominal());
  const SensorParams& truth = sim.as_built.sensor;
  EXPECT_NEAR(r.sensor.gain_e_per_dn / truth.gain_e_per_dn, 1.0, 0.05) << r.report.dump(1);
  EXPECT_NEAR(r.sensor.read_noise_e / truth.read_noise_e, 1.0, 0.05);
  EXPECT_NEAR(r.sensor.black_dn, truth.dark_level_dn, 0.5);
  // Pixels clip at the full well: black + full well / gain, less 3 dark sigmas.
  const double clip = truth.dark_level_dn + truth.full_well_e / truth.gain_e_per_dn;
  EXPECT_NEAR(r.sensor.saturation_dn, clip - 3, 3.0);
  int used = 0;
  for (const PhotonTransferPoint& p : r.points) used += p.used;
  EXPECT_GE(used, 4);
}

TEST(Noise, AnUnlitTargetIsADeviceError) {
  testing::SimulatedCalibrationRig sim("projector: {peak_radiance_w_m2_sr: 1e-9}");
  EXPECT_THROW(CalibrateNoise(sim.rig, sim.Nominal()), DeviceError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
