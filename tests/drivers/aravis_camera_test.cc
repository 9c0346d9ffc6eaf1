// AravisCamera against Aravis's GigE Vision fake camera, served in this process on 127.0.0.1 and
// opened by IP (never by discovery). Frames travel through the real GVCP/GVSP stack.
#include "drivers/aravis_camera.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <optional>

#include "basis/error.h"
#include "drivers/demosaic.h"
#include "drivers/fake_gige_camera.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using std::chrono::milliseconds;

class AravisCameraTest : public ::testing::Test {
 protected:
  FakeGigECamera fake_;

  static AravisCameraOptions Options(const std::string& pixel_format = "Mono8") {
    AravisCameraOptions options;
    options.ip = FakeGigECamera::kAddress;
    options.pixel_format = pixel_format;
    options.region_width = 64;
    options.region_height = 48;
    return options;
  }
};

// Aravis's own fill pattern (arvfakecamera.c, arv_fake_camera_diagonal_ramp) is an independent
// reference: Mono8 pixel = ((x + y + frame_id) % 255) * scale, Mono16 pixel =
// ((256 x + 256 frame_id + 256 y) % 65535) * scale, clamped, with
// scale = 1 + GainRaw + log10(ExposureTimeAbs / 10000 us).
uint16_t RampValue(int x, int y, uint64_t frame_id, double scale, bool mono16) {
  const double v = mono16 ? static_cast<double>((256 * (x + frame_id + y)) % 65535) * scale
                          : static_cast<double>((x + frame_id + y) % 255) * scale;
  return static_cast<uint16_t>(std::clamp(v, 0.0, mono16 ? 65535.0 : 255.0));
}

void ExpectRamp(const Frame& frame, double scale, bool mono16) {
  ASSERT_EQ(frame.data.size(), static_cast<size_t>(frame.width * frame.height));
  int mismatches = 0;
  for (int y = 0; y < frame.height; ++y) {
    for (int x = 0; x < frame.width; ++x) {
      const uint16_t expected = RampValue(x, y, frame.frame_id, scale, mono16);
      if (frame.data[static_cast<size_t>(y * frame.width + x)] != expected && mismatches++ < 3) {
        ADD_FAILURE() << "pixel " << x << "," << y << " of frame " << frame.frame_id << ": "
                      << frame.data[static_cast<size_t>(y * frame.width + x)] << " != " << expected;
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
}

TEST_F(AravisCameraTest, OpensByIpAndDescribesTheCamera) {
  AravisCameraOptions options = Options("");  // no format: the deepest one offered
  AravisCamera camera(options);
  const CameraInfo info = camera.Info();
  EXPECT_EQ(info.id, "127.0.0.1");
  EXPECT_EQ(info.model, "Aravis Fake");
  EXPECT_EQ(info.width, 64);
  EXPECT_EQ(info.height, 48);
  EXPECT_EQ(info.gain_unit, "raw");
  EXPECT_EQ(camera.PixelFormatName(), "Mono12");  // first of SupportedPixelFormats() offered
  EXPECT_EQ(info.bit_depth, 12);
  EXPECT_EQ(camera.SerialNumber(), fake_.Serial());
  EXPECT_EQ(camera.Describe(), "camera 127.0.0.1 (Aravis Fake, serial ZBRDF-FAKE)");
}

TEST_F(AravisCameraTest, OpeningTurnsAutomaticGainOffAndArmsTheSoftwareTrigger) {
  // Register addresses and values from the fake's GenICam description (arv-fake-camera.xml).
  constexpr uint32_t kGainAuto = 0x114, kTriggerMode = 0x300, kTriggerSource = 0x304;
  fake_.WriteRegister(kGainAuto, 2);  // Continuous
  fake_.WriteRegister(kTriggerMode, 0);
  AravisCamera camera(Options("Mono8"));
  EXPECT_EQ(fake_.ReadRegister(kGainAuto), 1u);       // Off
  EXPECT_EQ(fake_.ReadRegister(kTriggerMode), 1u);    // On
  EXPECT_EQ(fake_.ReadRegister(kTriggerSource), 1u);  // Software
  camera.SetTriggerMode(TriggerMode::kHardwareLine);
  EXPECT_EQ(fake_.ReadRegister(kTriggerSource), 0u);  // Line0
}

TEST_F(AravisCameraTest, Mono8AndMono16UnpackToAravissOwnRamp) {
  {
    AravisCamera camera(Options("Mono8"));
    EXPECT_EQ(camera.SetExposure(10000), 10000);  // scale 1
    for (int i = 0; i < 3; ++i) {
      const Frame frame = camera.Grab(milliseconds(1000));
      EXPECT_EQ(frame.layout, PixelLayout::kMono);
      EXPECT_EQ(frame.bit_depth, 8);
      ExpectRamp(frame, 1.0, false);
    }
  }
  AravisCamera camera(Options("Mono16"));
  camera.SetExposure(10000);
  const Frame frame = camera.Grab(milliseconds(1000));
  EXPECT_EQ(frame.bit_depth, 16);
  ExpectRamp(frame, 1.0, true);
}

TEST_F(AravisCameraTest, ExposureAndGainRoundTripAndReachTheSensor) {
  AravisCameraOptions options = Options("Mono8");
  options.exposure_max_us = 200000;
  AravisCamera camera(options);
  EXPECT_EQ(camera.Info().min_exposure_us, 10);      // the fake's ExposureTimeAbs minimum
  EXPECT_EQ(camera.Info().max_exposure_us, 200000);  // the rig's limit is tighter
  EXPECT_EQ(camera.SetExposure(100000), 100000);
  EXPECT_EQ(camera.SetGain(3), 3);
  const Frame frame = camera.Grab(milliseconds(1000));
  EXPECT_EQ(frame.exposure_us, 100000);
  EXPECT_EQ(frame.gain, 3);
  ExpectRamp(frame, 1.0 + 3.0 + std::log10(100000.0 / 10000.0), false);  // scale 5

  try {
    camera.SetExposure(500000);
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("camera 127.0.0.1 (Aravis Fake"), std::string::npos) << message;
    EXPECT_NE(message.find("ExposureTimeAbs: 500000 us is outside the allowed range [10, 200000]"),
              std::string::npos)
        << message;
  }
  EXPECT_THROW(camera.SetExposure(5), DeviceError);
  try {
    camera.SetGain(11);
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("GainRaw: 11 is outside [0, 10]"), std::string::npos)
        << e.what();
  }
}

// The samples of frame `index` for a format: distinct per frame and per pixel, within range.
std::vector<uint16_t> Generated(uint64_t index, size_t n, int bit_depth) {
  std::vector<uint16_t> samples(n);
  const uint32_t mask = (1u << bit_depth) - 1u;
  for (size_t i = 0; i < n; ++i) {
    samples[i] = static_cast<uint16_t>((index * 7919u + i * 2654435761u) % (mask + 1u));
  }
  return samples;
}

TEST_F(AravisCameraTest, FramesChosenPerTriggerArriveBitExactInEveryFormat) {
  fake_.SetFrameSource([](const FakeFrameRequest& request, std::vector<uint16_t>* samples) {
    const size_t n = static_cast<size_t>(request.width * request.height) *
                     static_cast<size_t>(SamplesPerPixel(request.layout));
    *samples = Generated(request.index, n, request.bit_depth);
  });
  const std::vector<std::pair<std::string, PixelLayout>> formats = {
      {"Mono8", PixelLayout::kMono},
      {"Mono12", PixelLayout::kMono},
      {"Mono12Packed", PixelLayout::kMono},
      {"Mono12p", PixelLayout::kMono},
      {"Mono16", PixelLayout::kMono},
      {"BayerRG8", PixelLayout::kBayerRGGB},
      {"BayerGB8", PixelLayout::kBayerGBRG},
      {"BayerRG12", PixelLayout::kBayerRGGB},
      {"BayerRG12Packed", PixelLayout::kBayerRGGB},
      {"BayerRG12p", PixelLayout::kBayerRGGB},
      {"BayerRG16", PixelLayout::kBayerRGGB},
      {"BayerGB16", PixelLayout::kBayerGBRG},
      {"RGB8", PixelLayout::kRgb},
      {"BGR8", PixelLayout::kRgb},
  };
  for (const auto& [name, layout] : formats) {
    AravisCamera camera(Options(name));
    for (int k = 0; k < 2; ++k) {
      const Frame frame = camera.Grab(milliseconds(1000));
      const uint64_t index = fake_.FramesFilled() - 1;  // one fill per software trigger
      EXPECT_EQ(frame.layout, layout) << name;
      EXPECT_EQ(frame.bit_depth, FindPixelFormat(name)->bit_depth) << name;
      EXPECT_EQ(frame.data, Generated(index, frame.data.size(), frame.bit_depth)) << name;
    }
  }
  EXPECT_EQ(fake_.LastSourceError(), "");
}

TEST_F(AravisCameraTest, Bayer16FramesDemosaicToTheColorTheSimulatorChose) {
  const uint16_t r = 50000, g = 20000, b = 3000;
  fake_.SetFrameSource([&](const FakeFrameRequest& request, std::vector<uint16_t>* samples) {
    samples->resize(static_cast<size_t>(request.width * request.height));
    for (int y = 0; y < request.height; ++y) {
      for (int x = 0; x < request.width; ++x) {
        (*samples)[static_cast<size_t>(y * request.width + x)] =
            (y % 2 == 0) ? (x % 2 == 0 ? r : g) : (x % 2 == 0 ? g : b);  // RGGB
      }
    }
  });
  AravisCamera camera(Options("BayerRG16"));
  const cv::Mat rgb = DemosaicToRgb(camera.Grab(milliseconds(1000)));
  EXPECT_EQ(rgb.at<cv::Vec3f>(20, 30), cv::Vec3f(r, g, b));
}

TEST_F(AravisCameraTest, APixelFormatTheCameraLacksListsWhatItOffers) {
  try {
    AravisCamera camera(Options("BayerRG10"));
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("camera 127.0.0.1 (Aravis Fake, serial ZBRDF-FAKE): PixelFormat "
                           "'BayerRG10' is not offered; the camera offers "),
              std::string::npos)
        << message;
    for (const char* offered : {"Mono8", "Mono16", "RGB8", "BayerRG8", "BayerRG16"}) {
      EXPECT_NE(message.find(offered), std::string::npos) << offered << " in " << message;
    }
  }
}

// Every frame of the fixture's source is self-consistent (sample i = (k + i) % 251); a buffer
// with missing packets would mix stale and fresh data.
void ConsistentSource(const FakeFrameRequest& request, std::vector<uint16_t>* samples) {
  samples->resize(static_cast<size_t>(request.width * request.height));
  for (size_t i = 0; i < samples->size(); ++i) {
    (*samples)[i] = static_cast<uint16_t>((request.index % 251 + i) % 251);
  }
}

TEST_F(AravisCameraTest, FramesWithLostPacketsAreCapturedAgainNeverReturned) {
  fake_.SetFrameSource(&ConsistentSource);
  fake_.SetLostPacketRatio(0.1);  // 64x48 Mono8 = 5 packets: 41% of frames lose one or more
  AravisCameraOptions options = Options("Mono8");
  options.retries = 25;
  options.frame_retention_us = 20000;
  AravisCamera camera(options);
  for (int i = 0; i < 20; ++i) {
    const Frame frame = camera.Grab(milliseconds(200));
    const uint16_t k = frame.data[0];
    for (size_t j = 0; j < frame.data.size(); ++j) {
      ASSERT_EQ(frame.data[j], (k + j) % 251) << "frame " << i << " sample " << j;
    }
  }
  const AravisCameraStats stats = camera.Stats();
  EXPECT_EQ(stats.frames, 20u);
  // P(no loss in 20 frames) = 0.59^20 < 3e-5.
  EXPECT_GT(stats.incomplete_frames + stats.timeouts, 0u);
}

TEST_F(AravisCameraTest, WhenEveryFrameIsIncompleteGrabGivesUpAfterTheRetries) {
  fake_.SetLostPacketRatio(1.0);
  AravisCameraOptions options = Options("Mono8");
  options.retries = 2;
  options.frame_retention_us = 20000;
  AravisCamera camera(options);
  const auto start = std::chrono::steady_clock::now();
  try {
    camera.Grab(milliseconds(100));
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("camera 127.0.0.1 (Aravis Fake"), std::string::npos) << message;
    EXPECT_NE(message.find("no complete frame after 3 software triggers"), std::string::npos)
        << message;
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  fake_.SetLostPacketRatio(0.0);
  EXPECT_NO_THROW(camera.Grab(milliseconds(1000)));  // the link recovered, so does the camera
}

TEST_F(AravisCameraTest, ACameraThatStopsAnsweringFailsQuicklyAndNamesItself) {
  // Declared before the camera so that it outlives it (see the end of the test).
  std::optional<FakeGigECamera> revived;
  AravisCamera camera(Options("Mono8"));
  camera.Grab(milliseconds(1000));
  fake_.Stop();
  auto start = std::chrono::steady_clock::now();
  try {
    camera.Grab(milliseconds(500));
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("camera 127.0.0.1 (Aravis Fake, serial ZBRDF-FAKE): TriggerSoftware"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("stopped answering"), std::string::npos) << message;
  }
  // Aravis waits 5 x 500 ms for a GVCP acknowledge.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(4));
  start = std::chrono::steady_clock::now();
  EXPECT_THROW(camera.Grab(milliseconds(500)), DeviceError);  // known dead: no new wait
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(100));
  // Releasing a camera that is gone costs Aravis ~10 s of GVCP timeouts (closing the stream
  // channel, leaving control); a camera back on the address lets the teardown finish at once.
  revived.emplace();
}

TEST_F(AravisCameraTest, ACameraControlledByAnotherApplicationIsReported) {
  AravisCamera first(Options("Mono8"));
  try {
    AravisCamera second(Options("Mono8"));
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("camera 127.0.0.1: another application controls this "
                                         "camera"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(first.Grab(milliseconds(1000)).width, 64);  // the controller is undisturbed
}

TEST_F(AravisCameraTest, NoCameraAtTheAddressIsADeviceError) {
  fake_.Stop();
  try {
    AravisCamera camera(Options("Mono8"));
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("camera 127.0.0.1: no GigE Vision camera answers"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(AravisCameraTest, LineTriggerWithoutPulsesTimesOutAndSoftwareTriggerResumes) {
  AravisCameraOptions options = Options("Mono8");
  options.trigger_mode = TriggerMode::kHardwareLine;
  options.retries = 1;
  AravisCamera camera(options);
  const auto start = std::chrono::steady_clock::now();
  try {
    camera.Grab(milliseconds(150));
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("no frame triggered on Line0 within 300 ms"),
              std::string::npos)
        << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  camera.SetTriggerMode(TriggerMode::kSoftware);
  EXPECT_EQ(camera.Grab(milliseconds(1000)).data.size(), 64u * 48u);
}

TEST_F(AravisCameraTest, ATriggerLineTheCameraLacksListsTheSources) {
  AravisCameraOptions options = Options("Mono8");
  options.trigger_mode = TriggerMode::kHardwareLine;
  options.trigger_line = "Line1";
  try {
    AravisCamera line1(options);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("TriggerSource 'Line1' is not offered; it offers "
                                         "Line0, Software"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(AravisCameraTest, FramesAreTimestampedOnTheGivenClock) {
  SteadyClock clock;
  AravisCamera camera(Options("Mono8"), &clock);
  const int64_t before = clock.NowUs();
  const Frame a = camera.Grab(milliseconds(1000));
  const Frame b = camera.Grab(milliseconds(1000));
  EXPECT_GE(a.timestamp_us, before);
  EXPECT_GT(b.timestamp_us, a.timestamp_us);
  EXPECT_LE(b.timestamp_us, clock.NowUs());
  EXPECT_GT(b.frame_id, a.frame_id);
}

TEST_F(AravisCameraTest, SerialNumbersAreCheckedAndResolvedWithoutDiscovery) {
  AravisCameraOptions wrong = Options("Mono8");
  wrong.serial = "OTHER-CAMERA";
  try {
    AravisCamera camera(wrong);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("expects serial 'OTHER-CAMERA'"), std::string::npos)
        << e.what();
  }

  const std::string directory = (std::filesystem::temp_directory_path() /
                                 ("zbrdf-cameras-" + std::to_string(getpid()) + ".yaml"))
                                    .string();
  WriteCameraDirectory(directory, {{"ZBRDF-FAKE", "127.0.0.1", "Aravis", "Fake"}});
  AravisCameraOptions by_serial = Options("Mono8");
  by_serial.ip.clear();
  by_serial.serial = "ZBRDF-FAKE";
  by_serial.camera_directory = directory;
  {
    AravisCamera camera(by_serial);
    EXPECT_EQ(camera.Info().id, "ZBRDF-FAKE");
    EXPECT_EQ(camera.Grab(milliseconds(1000)).width, 64);
  }
  by_serial.serial = "UNKNOWN";
  try {
    AravisCamera camera(by_serial);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("run `zbrdf devices --save`"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(directory);
}

TEST(CameraDirectoryTest, EntriesAreMergedBySerial) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("zbrdf-directory-" + std::to_string(getpid()) + "/cameras.yaml"))
                               .string();
  WriteCameraDirectory(path, {{"A", "192.0.2.1", "V", "M1"}, {"B", "192.0.2.2", "V", "M2"}});
  WriteCameraDirectory(path, {{"B", "192.0.2.3", "V", "M2"}});
  const auto entries = ReadCameraDirectory(path);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].ip, "192.0.2.1");
  EXPECT_EQ(entries[1].ip, "192.0.2.3");
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());
  EXPECT_TRUE(ReadCameraDirectory(path).empty());
  EXPECT_TRUE(IsIpv4Address("127.0.0.1"));
  EXPECT_FALSE(IsIpv4Address("300.1.2.3"));
  EXPECT_EQ(LocalInterfaceFor("127.0.0.1"), "127.0.0.1");
  EXPECT_THROW(LocalInterfaceFor("camera.local"), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
