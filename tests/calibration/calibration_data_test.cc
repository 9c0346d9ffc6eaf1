#include "calibration/calibration_data.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "basis/error.h"
#include "tests/calibration/calibration_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

CalibrationData Sample(const Rig& design) {
  CalibrationData d = NewCalibration(design);
  Misalignment m;
  m.camera_tilt_deg[0] = 0.25;
  m.projector_offset_mm = {0, 0, 0.5};
  d.misalignment = m;
  d.sensor = SensorCalibration{39.5, 41.0, 63.8, 4050};
  ProjectorResponseCalibration r;
  for (int i = 0; i < 256; ++i) r.response.push_back(std::pow(i / 255.0, 2.2));
  r.black_fraction = 0.002;
  d.projector_response = r;
  d.projector_flat = PixelField{design.projector.lens.width, design.projector.lens.height,
                                std::vector<float>(static_cast<size_t>(design.projector.lens.width) *
                                                       design.projector.lens.height, 0.9f)};
  d.camera_flat = PixelField{design.camera.width, design.camera.height,
                             std::vector<float>(static_cast<size_t>(design.camera.width) * design.camera.height, 1.1f)};
  d.camera_flat_source = "gray card";
  d.scale_rgb = std::array<double, 3>{1.01, 0.99, 1.02};
  d.reports["noise"] = {{"gain_e_per_dn", 39.5}};
  return d;
}

TEST(CalibrationData, SaveLoadRoundTrip) {
  const Rig design = ApplyPreset(LoadRig(testing::SourceRig("thesis.yaml")), Preset::kFast);
  const std::string folder = testing::TempFolder("roundtrip");
  const CalibrationData d = Sample(design);
  SaveCalibration(folder, d);
  const CalibrationData back = LoadCalibration(folder);
  EXPECT_EQ(back.rig_hash, d.rig_hash);
  EXPECT_EQ(back.Steps(), (std::vector<std::string>{"geometry", "noise", "projector", "graycard"}));
  EXPECT_EQ(back.misalignment->camera_tilt_deg[0], 0.25);
  EXPECT_EQ(back.misalignment->projector_offset_mm.z, 0.5);
  EXPECT_EQ(back.sensor->gain_e_per_dn, 39.5);
  EXPECT_EQ(back.projector_response->response, d.projector_response->response);
  EXPECT_EQ(back.projector_flat->value, d.projector_flat->value);
  EXPECT_EQ(back.camera_flat->value, d.camera_flat->value);
  EXPECT_EQ(back.camera_flat_source, "gray card");
  EXPECT_EQ(*back.scale_rgb, *d.scale_rgb);
  EXPECT_EQ(back.reports["noise"]["gain_e_per_dn"], 39.5);
  std::filesystem::remove_all(folder);
}

TEST(CalibrationData, ApplyReplacesNominalValues) {
  const Rig design = ApplyPreset(LoadRig(testing::SourceRig("thesis.yaml")), Preset::kFast);
  const CalibrationData d = Sample(design);
  const RigCalibration nominal = LoadRigCalibration(design, "", testing::TestCacheDir());
  const RigCalibration c = ApplyCalibration(design, d, "calibration: test", testing::TestCacheDir());
  EXPECT_EQ(c.source, "calibration: test");
  EXPECT_EQ(c.gain_e_per_dn, 39.5);
  EXPECT_EQ(c.read_noise_e, 41.0);
  EXPECT_EQ(c.black_dn, 63.8);
  EXPECT_EQ(c.saturation_dn, 4050);
  EXPECT_NEAR(c.projector_response[128], std::pow(128 / 255.0, 2.2), 1e-15);
  EXPECT_EQ(c.projector_black_fraction, 0.002);
  EXPECT_EQ(c.projector_flat_field[1000], 0.9f);
  EXPECT_EQ(c.channel_scale[2], 1.02);
  // The misaligned rig's maps, and the camera flat field on its response.
  const OpticalSystem optics(CalibratedRig(design, d));
  const RigMaps maps = LoadOrBuildRigMaps(optics, testing::TestCacheDir());
  const RigCalibration geometric = NominalCalibration(CalibratedRig(design, d), maps);
  int compared = 0;
  for (size_t i = 0; i < c.camera_response.size(); i += 37) {
    EXPECT_FLOAT_EQ(c.camera_response[i], 1.1f * geometric.camera_response[i]);
    compared += geometric.camera_response[i] > 0;
  }
  EXPECT_GT(compared, 100);
  EXPECT_NE(c.camera_direction, nominal.camera_direction) << "maps traced for the calibrated geometry";
}

TEST(CalibrationData, WrongRigAndDamageAreNamedErrors) {
  const Rig design = ApplyPreset(LoadRig(testing::SourceRig("thesis.yaml")), Preset::kFast);
  const Rig full = LoadRig(testing::SourceRig("thesis.yaml"));
  const std::string folder = testing::TempFolder("errors");
  EXPECT_THROW(LoadCalibration(folder), InputError);
  SaveCalibration(folder, Sample(design));
  try {
    LoadRigCalibration(full, folder, testing::TestCacheDir());
    FAIL() << "a fast-preset calibration applied to the full-resolution rig";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--preset"), std::string::npos) << e.what();
  }
  std::filesystem::remove(folder + "/projector_flat.exr");
  EXPECT_THROW(LoadCalibration(folder), InputError);
  std::ofstream(folder + "/calibration.json") << "{\"format\": \"zbrdf-calibration-v1\", \"rig\": 3}";
  EXPECT_THROW(LoadCalibration(folder), InputError);
  std::filesystem::remove_all(folder);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
