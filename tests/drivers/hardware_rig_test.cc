#include "drivers/hardware_rig.h"

#include <gtest/gtest.h>

#include "basis/error.h"
#include "drivers/dlpc350_emulator.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

std::string ErrorOf(const std::string& yaml) {
  try {
    ParseHardwareRig(yaml, "lab.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(HardwareRigTest, TheDocumentedExampleParses) {
  const HardwareRig rig = LoadHardwareRig(ZBRDF_SOURCE_DIR "/docs/examples/lab-rig.yaml");
  EXPECT_EQ(rig.camera.ip, "192.0.2.10");
  EXPECT_EQ(rig.camera.interface_ip, "192.0.2.1");
  EXPECT_EQ(rig.camera.pixel_format, "BayerRG12");
  ASSERT_TRUE(rig.camera.gain.has_value());
  EXPECT_EQ(*rig.camera.gain, 0);
  EXPECT_EQ(rig.camera.exposure_min_us, 20);
  EXPECT_EQ(rig.camera.exposure_max_us, 2000000);
  EXPECT_EQ(rig.camera.timeout_ms, 3000);
  EXPECT_EQ(rig.camera.retries, 3);
  EXPECT_EQ(rig.camera.packet_size, 8192);
  EXPECT_EQ(rig.camera.trigger_line, "Line0");
  EXPECT_EQ(rig.projector.x11_output, "HDMI-1");
  EXPECT_TRUE(rig.projector.usb);
  EXPECT_EQ(rig.projector.usb_vendor_id, 0x0451);
  EXPECT_EQ(rig.projector.usb_product_id, 0x6401);
  ASSERT_TRUE(rig.projector.led_currents.has_value());
  EXPECT_EQ(rig.projector.led_currents->green, 135);
  EXPECT_EQ(rig.sync.mode, SyncMode::kHardware);
  EXPECT_EQ(rig.sync.hardware_settle_ms, 40);
  EXPECT_EQ(rig.sync.software_settle_ms, 120);

  const AravisCameraOptions options = CameraOptionsFromRig(rig);
  EXPECT_EQ(options.trigger_mode, TriggerMode::kHardwareLine);
  EXPECT_EQ(options.trigger_line, "Line0");
  EXPECT_EQ(options.ip, "192.0.2.10");
}

TEST(HardwareRigTest, TheFakeRigExampleParses) {
  const HardwareRig rig = LoadHardwareRig(ZBRDF_SOURCE_DIR "/docs/examples/fake-rig.yaml");
  EXPECT_EQ(rig.camera.ip, "127.0.0.1");
  EXPECT_EQ(rig.camera.region_width, 256);
  EXPECT_EQ(rig.projector.x11_output, "screen");
  EXPECT_FALSE(rig.projector.usb);
  EXPECT_EQ(rig.sync.mode, SyncMode::kSoftware);
  EXPECT_EQ(CameraOptionsFromRig(rig).trigger_mode, TriggerMode::kSoftware);
}

TEST(HardwareRigTest, AnErrorNamesTheFileAndTheField) {
  EXPECT_EQ(ErrorOf("camera:\n  ip: 300.1.2.3\nprojector:\n  x11_output: HDMI-1\n"),
            "rig file lab.yaml: camera.ip '300.1.2.3' is not an IPv4 address");
}

TEST(HardwareRigTest, EveryProblemIsReportedAtOnce) {
  const std::string message = ErrorOf(
      "camera:\n  ip: 127.0.0.1\n  retries: -1\n  pixel_format: YUV422\n"
      "  exposure_min_us: 500\n  exposure_max_us: 100\n  trigger_line: Pin3\n"
      "projector:\n  refresh_hz: fast\n  usb: {bus: 1}\n  led_currents: {red: 300, green: 1, "
      "blue: 1}\nsync:\n  mode: magic\n");
  for (const char* expected :
       {"camera.retries must be in [0, 100] (got -1)", "camera.pixel_format 'YUV422'",
        "camera.exposure_min_us (500) must not exceed camera.exposure_max_us (100)",
        "camera.trigger_line must name an input line", "projector.x11_output is required",
        "projector.refresh_hz must be a number (got 'fast')",
        "projector.usb needs both bus and address",
        "projector.led_currents.red must be in [0, 255]",
        "sync.mode must be hardware or software (got 'magic')"}) {
    EXPECT_NE(message.find(expected), std::string::npos) << expected << "\n in: " << message;
  }
}

TEST(HardwareRigTest, UnknownAndMissingFieldsAreErrors) {
  const std::string unknown = ErrorOf(
      "camera: {ip: 127.0.0.1, exposure_max: 5}\nprojector: {x11_output: screen}\n"
      "sink: {mode: software}\n");
  EXPECT_NE(unknown.find("camera.exposure_max is not a known field"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("sink is not a known field"), std::string::npos) << unknown;
  EXPECT_NE(ErrorOf("projector: {x11_output: screen}\n").find("camera section is missing"),
            std::string::npos);
  EXPECT_NE(ErrorOf("camera: {pixel_format: Mono8}\nprojector: {x11_output: screen}\n")
                .find("camera needs ip (preferred) or serial"),
            std::string::npos);
  EXPECT_NE(ErrorOf("camera: [1, 2\n").find("not valid YAML"), std::string::npos);
  EXPECT_THROW(LoadHardwareRig("/nonexistent/rig.yaml"), InputError);
}

TEST(HardwareRigTest, VideoSetupOfTheDlpc350) {
  auto state = std::make_shared<Dlpc350Emulator::State>();
  state->standby = true;
  state->led_enable = 0x00;
  state->input_source = 0x01;  // test pattern generator
  Dlpc350 control(std::make_unique<Dlpc350Emulator>(state));
  RigProjectorConfig config;
  config.led_currents = Dlpc350LedCurrents{10, 20, 30};
  config.trigger_output = 2;
  ConfigureDlpc350ForVideo(control, config, SyncMode::kHardware);
  EXPECT_FALSE(state->standby);
  EXPECT_EQ(state->display_mode, 0);
  EXPECT_EQ(state->input_source, 0x08);  // parallel port, 24 bit
  EXPECT_EQ(state->led_enable, 0x0F);
  EXPECT_EQ(state->led_currents, (std::vector<uint8_t>{10, 20, 30}));
  EXPECT_EQ(state->trig_out2, (std::vector<uint8_t>{0x00, 0xBB}));  // active high, no delay

  // A controller that reports an error stops the setup with its reasons.
  state->hardware_status = 0x81;
  try {
    ConfigureDlpc350ForVideo(control, config, SyncMode::kSoftware);
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("sequencer error"), std::string::npos) << e.what();
  }
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
