#include "simulate/virtual_rig.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "basis/error.h"
#include "brdf/material_spec.h"
#include "tests/rig/rig_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

VirtualRig MakeRig(uint64_t seed, const std::string& material = "lambert:0.3") {
  VirtualRig::Options options;
  options.seed = seed;
  options.cache_dir = testing::TestCacheDir();
  return VirtualRig(ApplyPreset(LoadRig(testing::SourceRig("thesis.yaml")), Preset::kFast),
                    MakeBrdf(material), options);
}

Pattern White(const ProjectorInfo& info) {
  Pattern p;
  p.width = info.width;
  p.height = info.height;
  p.bit_depth = info.bit_depth;
  p.levels.assign(static_cast<size_t>(p.width) * p.height, 255);
  return p;
}

TEST(VirtualRigTest, TimingModelChargesFramePeriodExposureAndReadout) {
  VirtualRig rig = MakeRig(1);
  Camera& camera = rig.camera();
  const int64_t t0 = rig.clock().NowUs();
  camera.SetExposure(10000);
  camera.Grab(std::chrono::milliseconds(1000));
  // Exposure 10 ms + readout 30 ms.
  EXPECT_EQ(rig.clock().NowUs() - t0, 40000);
  camera.Grab(std::chrono::milliseconds(1000));
  // The next frame starts one frame period (1/15 s) after the first: 66667 + 40000.
  EXPECT_EQ(rig.clock().NowUs() - t0, 66667 + 40000);
  camera.SetExposure(200000);
  rig.clock().SleepUs(100000);  // a projector settle, charged by the session
  const Frame f = camera.Grab(std::chrono::milliseconds(1000));
  EXPECT_EQ(f.timestamp_us, t0 + 66667 + 40000 + 100000);
  EXPECT_EQ(f.exposure_us, 200000);
}

TEST(VirtualRigTest, FramesShowWhatTheProjectorShowsAndRepeatForTheSameIndex) {
  VirtualRig a = MakeRig(7), b = MakeRig(7);
  for (VirtualRig* rig : {&a, &b}) {
    rig->projector().Show(White(rig->projector().Info()));
    rig->camera().SetExposure(20000);
    rig->camera().SetNextFrameIndex(42);
  }
  const Frame fa = a.camera().Grab(std::chrono::milliseconds(100));
  const Frame fb = b.camera().Grab(std::chrono::milliseconds(100));
  EXPECT_EQ(fa.data, fb.data);
  const CameraInfo info = a.camera().Info();
  EXPECT_EQ(fa.width, info.width);
  EXPECT_EQ(fa.layout, PixelLayout::kBayerRGGB);
  // Dark projector: only the black level and noise.
  VirtualRig dark = MakeRig(7);
  dark.camera().SetExposure(20000);
  const Frame fd = dark.camera().Grab(std::chrono::milliseconds(100));
  double lit_sum = 0, dark_sum = 0;
  for (size_t i = 0; i < fa.data.size(); ++i) {
    lit_sum += fa.data[i];
    dark_sum += fd.data[i];
  }
  EXPECT_GT(lit_sum, 1.2 * dark_sum);
}

TEST(VirtualRigTest, PatternsAnnouncedAheadGiveTheFramesOfPatternsShownAlone) {
  // One rig is told the patterns ahead, the other is not; both show the same sequence. A
  // glossy material (a Lambertian's frames need no transport entries at all).
  const std::string material = "ggx:alpha=0.2,F0=0.04,kd=0.2";
  VirtualRig told = MakeRig(5, material), alone = MakeRig(5, material);
  const ProjectorInfo info = told.projector().Info();
  std::vector<Pattern> random(4, White(info));
  uint64_t state = 3;
  for (Pattern& p : random) {
    for (uint16_t& level : p.levels) level = static_cast<uint16_t>((state = HashMix(state)) % 256);
  }
  Pattern wrong_size = White(info);
  wrong_size.width -= 1;
  told.projector().Upcoming(std::vector<Pattern>{random[0], random[1], random[2]});
  // The window in order, with a pattern not in it (white) between; then a window with a pattern
  // the projector cannot show, whose valid neighbour is still rendered right.
  const std::vector<Pattern> sequence = {random[0], White(info), random[1], random[2], random[3]};
  uint64_t index = 10;
  for (size_t i = 0; i < sequence.size(); ++i) {
    if (i == 4) told.projector().Upcoming(std::vector<Pattern>{wrong_size, random[3]});
    for (VirtualRig* rig : {&told, &alone}) {
      rig->projector().Show(sequence[i]);
      rig->camera().SetExposure(5000);
      rig->camera().SetNextFrameIndex(index);
    }
    ++index;
    const Frame a = told.camera().Grab(std::chrono::milliseconds(100));
    const Frame b = alone.camera().Grab(std::chrono::milliseconds(100));
    EXPECT_EQ(a.data, b.data) << "pattern " << i;
  }
  EXPECT_EQ(static_cast<VirtualCamera&>(told.camera()).rates_rendered_ahead(), 3u);
  EXPECT_EQ(static_cast<VirtualCamera&>(told.camera()).rates_from_windows(), 3u);
  EXPECT_EQ(static_cast<VirtualCamera&>(alone.camera()).rates_from_windows(), 0u);
  EXPECT_THROW(told.projector().Show(wrong_size), InputError);
}

TEST(VirtualRigTest, RejectsBadExposuresAndPatterns) {
  VirtualRig rig = MakeRig(1);
  EXPECT_THROW(rig.camera().SetExposure(-5), DeviceError);
  EXPECT_THROW(rig.camera().SetExposure(1e9), DeviceError);
  Pattern p = White(rig.projector().Info());
  p.height += 1;
  EXPECT_THROW(rig.projector().Show(p), InputError);
}

TEST(VirtualRigTest, SwappingTheMaterialChangesTheFrames) {
  VirtualRig rig = MakeRig(3);
  rig.projector().Show(White(rig.projector().Info()));
  rig.camera().SetExposure(300);  // the fast preset's large pixels: ~3000 e- for albedo 0.9
  rig.camera().SetNextFrameIndex(1);
  const Frame gray = rig.camera().Grab(std::chrono::milliseconds(100));
  rig.SetMaterial(MakeBrdf("lambert:0.9"));
  rig.camera().SetNextFrameIndex(1);
  const Frame white = rig.camera().Grab(std::chrono::milliseconds(100));
  double g = 0, w = 0;
  for (size_t i = 0; i < gray.data.size(); ++i) {
    g += gray.data[i] - 64.0;
    w += white.data[i] - 64.0;
  }
  EXPECT_NEAR(w / g, 3.0, 0.05);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
