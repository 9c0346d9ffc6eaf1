#include "drivers/rig_sync.h"

#include <gtest/gtest.h>

#include "basis/error.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// Records what the capture does, with the model clock's time of each call.
struct Log {
  ModelClock clock;
  std::vector<std::pair<std::string, int64_t>> events;
};

class LoggingCamera final : public Camera {
 public:
  explicit LoggingCamera(Log* log) : log_(log) {}
  CameraInfo Info() const override { return {}; }
  double SetExposure(double us) override { return us; }
  void SetTriggerMode(TriggerMode mode) override {
    log_->events.push_back(
        {mode == TriggerMode::kSoftware ? "trigger-mode software" : "trigger-mode line",
         log_->clock.NowUs()});
  }
  Frame Grab(std::chrono::milliseconds) override {
    log_->events.push_back({"grab", log_->clock.NowUs()});
    Frame f;
    f.timestamp_us = log_->clock.NowUs();
    return f;
  }

 private:
  Log* log_;
};

class LoggingProjector final : public Projector {
 public:
  explicit LoggingProjector(Log* log) : log_(log) {}
  ProjectorInfo Info() const override { return {}; }
  void Show(const Pattern&) override {
    log_->clock.SleepUs(16000);  // showing takes a frame
    log_->events.push_back({"show", log_->clock.NowUs()});
  }

 private:
  Log* log_;
};

TEST(RigSyncTest, SoftwareSyncWaitsTheSettleTimeBeforeTriggering) {
  Log log;
  LoggingCamera camera(&log);
  LoggingProjector projector(&log);
  RigSyncConfig config;
  config.mode = SyncMode::kSoftware;
  config.software_settle_ms = 120;
  PatternCapture capture(camera, projector, log.clock, config);
  const Frame frame = capture.ShowAndGrab(Pattern{}, std::chrono::milliseconds(100));
  ASSERT_EQ(log.events.size(), 3u);
  EXPECT_EQ(log.events[0].first, "trigger-mode software");
  EXPECT_EQ(log.events[1], (std::pair<std::string, int64_t>{"show", 16000}));
  EXPECT_EQ(log.events[2], (std::pair<std::string, int64_t>{"grab", 16000 + 120000}));
  EXPECT_EQ(capture.last_show_us(), 16000);
  EXPECT_EQ(frame.timestamp_us - capture.last_show_us(), 120000);
}

TEST(RigSyncTest, HardwareSyncUsesTheLineTriggerAndItsOwnSettleTime) {
  Log log;
  LoggingCamera camera(&log);
  LoggingProjector projector(&log);
  RigSyncConfig config;
  config.mode = SyncMode::kHardware;
  config.hardware_settle_ms = 33.4;
  PatternCapture capture(camera, projector, log.clock, config);
  capture.ShowAndGrab(Pattern{}, std::chrono::milliseconds(100));
  ASSERT_EQ(log.events.size(), 3u);
  EXPECT_EQ(log.events[0].first, "trigger-mode line");
  EXPECT_EQ(log.events[2].second - log.events[1].second, 33400);
}

TEST(RigSyncTest, NamesRoundTripAndBadValuesAreRejected) {
  EXPECT_EQ(ParseSyncMode(SyncModeName(SyncMode::kHardware)), SyncMode::kHardware);
  EXPECT_EQ(ParseSyncMode(SyncModeName(SyncMode::kSoftware)), SyncMode::kSoftware);
  EXPECT_THROW(ParseSyncMode("vsync"), InputError);
  Log log;
  LoggingCamera camera(&log);
  LoggingProjector projector(&log);
  RigSyncConfig config;
  config.software_settle_ms = -1;
  EXPECT_THROW(PatternCapture(camera, projector, log.clock, config), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
