// AravisCamera against arv-fake-gv-camera-0.8 running as a separate process on 127.0.0.1. The
// test starts the process, records its PID, and signals only that PID at the end.
#include <gtest/gtest.h>
#include <signal.h>

#include <optional>

#include "basis/error.h"
#include "drivers/aravis_camera.h"
#include "test_processes.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using std::chrono::milliseconds;

AravisCameraOptions Options() {
  AravisCameraOptions options;
  options.ip = "127.0.0.1";
  options.pixel_format = "Mono8";
  options.region_width = 64;
  options.region_height = 48;
  options.exposure_us = 10000;
  return options;
}

TEST(FakeGigEProcessTest, CapturesFromTheFakeCameraProcess) {
  testing::FakeCameraProcess process("ZBRDF-PROC");
  ASSERT_GT(process.pid(), 0);
  {
    AravisCamera camera(Options());
    EXPECT_EQ(camera.SerialNumber(), "ZBRDF-PROC");
    for (int i = 0; i < 3; ++i) {
      const Frame frame = camera.Grab(milliseconds(2000));
      ASSERT_EQ(frame.width, 64);
      // Aravis's Mono8 ramp at exposure 10 ms, gain 0: (x + y + frame_id) % 255.
      for (int y = 0; y < frame.height; y += 7) {
        for (int x = 0; x < frame.width; x += 5) {
          EXPECT_EQ(frame.data[static_cast<size_t>(y * frame.width + x)],
                    (x + y + frame.frame_id) % 255);
        }
      }
    }
  }
  const pid_t pid = process.pid();
  process.Stop();
  EXPECT_NE(kill(pid, 0), 0);  // that process is gone (and reaped)
}

TEST(FakeGigEProcessTest, KillingTheCameraMidCaptureIsADeviceErrorNamingIt) {
  testing::FakeCameraProcess process("ZBRDF-PROC");
  std::optional<testing::FakeCameraProcess> revived;  // outlives the camera, see below
  AravisCamera camera(Options());
  camera.Grab(milliseconds(2000));
  process.Stop(SIGKILL);
  const auto start = std::chrono::steady_clock::now();
  try {
    camera.Grab(milliseconds(500));
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("camera 127.0.0.1 (Aravis Fake, serial ZBRDF-PROC)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(4));
  // Without a camera at the address, releasing it costs ~10 s of GVCP timeouts; a restarted
  // fake answers them.
  revived.emplace("ZBRDF-PROC");
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
