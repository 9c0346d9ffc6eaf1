// The X11 projector driver against a real X server: each test starts its own Xvfb (which picks a
// free display number) and reads the screen back with XGetImage.
#include "drivers/x11_display.h"

#include <gtest/gtest.h>

#include <random>

#include "basis/error.h"
#include "test_processes.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

class X11DisplayTest : public ::testing::Test {
 protected:
  testing::XvfbServer xvfb_;

  X11DisplayOptions Options() const {
    X11DisplayOptions options;
    options.display = xvfb_.display();
    options.output = "screen";  // Xvfb's only RandR output
    return options;
  }
};

Pattern RandomPattern(int width, int height, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> level(0, 255);
  Pattern p;
  p.width = width;
  p.height = height;
  p.bit_depth = 8;
  p.levels.resize(static_cast<size_t>(width * height));
  for (auto& v : p.levels) v = static_cast<uint16_t>(level(rng));
  return p;
}

TEST_F(X11DisplayTest, ShowsThePatternFullScreenAndItReadsBackExactly) {
  X11Display display(Options());
  const ProjectorInfo info = display.Info();
  EXPECT_EQ(info.id, "screen");
  EXPECT_EQ(info.width, 1024);
  EXPECT_EQ(info.height, 768);
  EXPECT_EQ(info.bit_depth, 8);
  for (unsigned seed : {1u, 2u}) {
    const Pattern pattern = RandomPattern(1024, 768, seed);
    display.Show(pattern);
    const X11Capture capture = display.ReadBack();
    ASSERT_EQ(capture.rgb.size(), 1024u * 768u * 3u);
    // Gray levels replicated to R, G and B, pixel for pixel, corners included.
    for (size_t i : {size_t{0}, size_t{1023}, size_t{1024 * 767}, size_t{1024 * 768 - 1},
                     size_t{1024 * 400 + 517}}) {
      EXPECT_EQ(capture.rgb[3 * i], pattern.levels[i]);
      EXPECT_EQ(capture.rgb[3 * i + 1], pattern.levels[i]);
      EXPECT_EQ(capture.rgb[3 * i + 2], pattern.levels[i]);
    }
    EXPECT_TRUE(CaptureMatches(capture, pattern));
  }
}

TEST_F(X11DisplayTest, ShowWaitsTheSettleFramesAndLatencyIsMeasured) {
  X11DisplayOptions options = Options();
  options.refresh_hz = 50;  // Xvfb reports no mode timing; 2 frames at 50 Hz = 40 ms
  X11Display display(options);
  EXPECT_EQ(display.RefreshHz(), 50);
  const Pattern pattern = RandomPattern(1024, 768, 3);
  const auto start = std::chrono::steady_clock::now();
  display.Show(pattern);
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(40));
  const auto latency =
      display.MeasureReadbackLatency(RandomPattern(1024, 768, 4), std::chrono::seconds(2));
  EXPECT_GT(latency.count(), 0);
  EXPECT_LT(latency.count(), 2000000);
  X11Display fallback(Options());
  EXPECT_EQ(fallback.RefreshHz(), 60);  // no timing from Xvfb, no override
}

TEST_F(X11DisplayTest, PatternsOfTheWrongSizeOrDepthAreRejected) {
  X11Display display(Options());
  Pattern small = RandomPattern(800, 600, 5);
  EXPECT_THROW(display.Show(small), InputError);
  Pattern deep = RandomPattern(1024, 768, 6);
  deep.bit_depth = 10;
  EXPECT_THROW(display.Show(deep), InputError);
  Pattern bright = RandomPattern(1024, 768, 7);
  bright.levels[5] = 256;
  EXPECT_THROW(display.Show(bright), InputError);
}

TEST_F(X11DisplayTest, AnUnknownOutputIsAnErrorListingTheOutputs) {
  X11DisplayOptions options = Options();
  options.output = "HDMI-1";
  try {
    X11Display display(options);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("output HDMI-1 does not exist"), std::string::npos) << message;
    EXPECT_NE(message.find("outputs: screen"), std::string::npos) << message;
  }
  const auto outputs = ListX11Outputs(xvfb_.display());
  ASSERT_EQ(outputs.size(), 1u);
  EXPECT_EQ(outputs[0].name, "screen");
  EXPECT_TRUE(outputs[0].active);
  EXPECT_EQ(outputs[0].width, 1024);
}

TEST_F(X11DisplayTest, ALostXServerIsADeviceErrorNotAnExit) {
  X11Display display(Options());
  xvfb_.Stop();
  EXPECT_THROW(display.Show(RandomPattern(1024, 768, 8)), DeviceError);
}

TEST(X11DisplayNoServerTest, AMissingDisplayIsADeviceError) {
  X11DisplayOptions options;
  options.display = ":65000";
  options.output = "screen";
  EXPECT_THROW(X11Display display(options), DeviceError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
