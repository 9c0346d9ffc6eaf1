// The rig self-test end to end: the in-process fake GigE camera on 127.0.0.1, an Xvfb display as
// the projector, and the DLPC350 emulator as its controller. A test projector models the light
// on the sample (what the camera sees follows the shown pattern `delay` after Show returns), and
// the fake camera's frame source renders it, so the latency measurement can be checked against a
// known delay.
#include "drivers/rig_check.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <mutex>

#include "drivers/aravis_camera.h"
#include "drivers/dlpc350_emulator.h"
#include "drivers/fake_gige_camera.h"
#include "test_processes.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

class LitSample final : public Projector {
 public:
  LitSample(X11Display& display, Clock& clock, int64_t delay_us)
      : display_(display), clock_(clock), delay_us_(delay_us) {}
  ProjectorInfo Info() const override { return display_.Info(); }
  void Show(const Pattern& pattern) override {
    display_.Show(pattern);
    double sum = 0;
    for (uint16_t v : pattern.levels) sum += v;
    const double level = sum / pattern.levels.size() / ((1 << pattern.bit_depth) - 1);
    std::lock_guard<std::mutex> lock(mutex_);
    const int64_t now = clock_.NowUs();
    previous_ = LevelLocked(now);
    current_ = level;
    shown_us_ = now;
  }
  // Fraction of full illumination on the sample at `now_us`.
  double Level(int64_t now_us) {
    std::lock_guard<std::mutex> lock(mutex_);
    return LevelLocked(now_us);
  }

 private:
  double LevelLocked(int64_t now_us) const {
    return now_us - shown_us_ >= delay_us_ ? current_ : previous_;
  }
  X11Display& display_;
  Clock& clock_;
  int64_t delay_us_;
  std::mutex mutex_;
  double previous_ = 0, current_ = 0;
  int64_t shown_us_ = 0;
};

class RigCheckTest : public ::testing::Test {
 protected:
  testing::XvfbServer xvfb_{"640x480x24"};
  FakeGigECamera fake_;
  SteadyClock clock_;

  std::unique_ptr<AravisCamera> OpenCamera() {
    AravisCameraOptions options;
    options.ip = FakeGigECamera::kAddress;
    options.pixel_format = "Mono12";
    options.region_width = 64;
    options.region_height = 48;
    return std::make_unique<AravisCamera>(options, &clock_);
  }
  X11DisplayOptions DisplayOptions() const {
    X11DisplayOptions options;
    options.display = xvfb_.display();
    options.output = "screen";
    return options;
  }
  static RigCheckOptions CheckOptions() {
    RigCheckOptions options;
    options.frames = 5;
    options.exposure_us = 1000;
    options.grab_timeout = std::chrono::milliseconds(1000);
    options.steady_state_ms = 200;
    return options;
  }
  static const RigCheckItem* Find(const RigCheckReport& report, const std::string& name) {
    for (const auto& item : report.items) {
      if (item.name == name) return &item;
    }
    ADD_FAILURE() << "no item " << name;
    return nullptr;
  }
};

TEST_F(RigCheckTest, ACameraThatSeesNothingFailsTheLevelsWithAReason) {
  fake_.SetFrameSource([](const FakeFrameRequest& r, std::vector<uint16_t>* samples) {
    samples->assign(static_cast<size_t>(r.width * r.height), 40);
  });
  auto camera = OpenCamera();
  X11Display display(DisplayOptions());
  RigSyncConfig sync;
  sync.software_settle_ms = 50;
  const RigCheckReport report =
      RunRigCheck(*camera, display, &display, nullptr, sync, clock_, CheckOptions());
  for (const char* passing : {"camera", "camera.frames", "projector.display",
                              "projector.readback_latency", "levels.dark"}) {
    const RigCheckItem* item = Find(report, passing);
    ASSERT_NE(item, nullptr);
    EXPECT_TRUE(item->passed) << passing << ": " << item->detail;
  }
  EXPECT_NE(Find(report, "camera.frames")->detail.find("5/5 frames"), std::string::npos);
  EXPECT_NE(Find(report, "projector.display")->detail.find("read back exactly"), std::string::npos);
  const RigCheckItem* white = Find(report, "levels.white");
  EXPECT_FALSE(white->passed);
  EXPECT_NE(white->detail.find("is the projector on"), std::string::npos) << white->detail;
  const RigCheckItem* latency = Find(report, "sync.latency");
  EXPECT_FALSE(latency->passed);
  EXPECT_NE(latency->detail.find("skipped"), std::string::npos) << latency->detail;
  EXPECT_FALSE(report.AllPassed());
  EXPECT_LT(report.seconds, 30);
}

TEST_F(RigCheckTest, TheMeasuredLatencyBracketsTheTrueDelayAndIsComparedWithTheSettleTime) {
  X11Display display(DisplayOptions());
  const int64_t delay_us = 30000;
  LitSample sample(display, clock_, delay_us);
  fake_.SetFrameSource([&](const FakeFrameRequest& r, std::vector<uint16_t>* samples) {
    const double level = sample.Level(clock_.NowUs());
    samples->assign(static_cast<size_t>(r.width * r.height),
                    static_cast<uint16_t>(40 + 3000 * level));
  });
  auto camera = OpenCamera();
  Dlpc350 control(std::make_unique<Dlpc350Emulator>());

  RigSyncConfig sync;
  sync.software_settle_ms = 100;
  RigCheckReport report =
      RunRigCheck(*camera, sample, &display, &control, sync, clock_, CheckOptions());
  for (const auto& item : report.items)
    EXPECT_TRUE(item.passed) << item.name << ": " << item.detail;
  EXPECT_NE(Find(report, "projector.control")->detail.find("firmware 3.0.3"), std::string::npos);
  const std::string detail = Find(report, "sync.latency")->detail;
  double low = 0, high = 0;
  ASSERT_EQ(std::sscanf(detail.c_str(), "light reached the sample %lf to %lf ms", &low, &high), 2)
      << detail;
  // The check takes a frame's trigger time as its exposure start; the fake renders the frame
  // when its thread serves the trigger (1 ms polling, more on a loaded machine). That lag is the
  // margin: the bracket must hold the true 30 ms to within it.
  const double lag_ms = 10;
  EXPECT_LE(low, 30.0 + lag_ms) << detail;
  EXPECT_GE(high, 30.0 - lag_ms) << detail;
  EXPECT_LE(low, high) << detail;
  EXPECT_LT(high - low, 30.0) << detail;

  sync.software_settle_ms = 10;  // shorter than the 30 ms the light needs
  report = RunRigCheck(*camera, sample, &display, &control, sync, clock_, CheckOptions());
  const RigCheckItem* latency = Find(report, "sync.latency");
  EXPECT_FALSE(latency->passed);
  EXPECT_NE(latency->detail.find("raise sync.software_settle_ms above"), std::string::npos)
      << latency->detail;
  EXPECT_TRUE(Find(report, "levels.white")->passed);  // levels are measured in steady state
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
