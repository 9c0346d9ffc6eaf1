// The libusb DLPC350 transport on its real code path (libusb -> usbdevfs ioctls), run under
// umockdev-run: the device is tests/drivers/data/dlpc350.umockdev (a LightCrafter-like HID
// device 0451:6401 on bus 1, address 2) and the USB traffic is replayed from
// tests/drivers/data/dlpc350.ioctl. umockdev fails an OUT transfer whose bytes differ from the
// script, so the replay checks every byte the driver sends; the replies are the script's IN
// URBs. Only CTest's drivers_dlpc350_usb_under_umockdev test runs this binary.
#include <gtest/gtest.h>

#include "basis/error.h"
#include "drivers/dlpc350.h"
#include "drivers/dlpc350_usb.h"

namespace zbrdf {
namespace {

Dlpc350UsbOptions UnderUmockdev() {
  Dlpc350UsbOptions options;
  // umockdev emulates usbdevfs transfers, not the kernel-driver (dis)connect ioctls.
  options.auto_detach_kernel_driver = false;
  return options;
}

Dlpc350Options FastTimeouts() {
  Dlpc350Options options;
  options.reply_timeout = std::chrono::milliseconds(200);
  options.retries = 1;
  return options;
}

TEST(Dlpc350UsbReplayTest, ReplaysTheScriptedSessionByteForByte) {
  Dlpc350 dlpc(std::make_unique<LibusbDlpc350Transport>(UnderUmockdev()), FastTimeouts());
  EXPECT_EQ(dlpc.Name(), "DLPC350 USB 001/002 (0451:6401)");

  const Dlpc350Status status = dlpc.GetStatus();
  EXPECT_TRUE(status.InitializationDone());
  EXPECT_TRUE(status.MemoryTestPassed());
  EXPECT_EQ(status.Problems(), "");

  dlpc.SetLedCurrents({0x64, 0x87, 0x82});
  const Dlpc350LedCurrents currents = dlpc.GetLedCurrents();
  EXPECT_EQ(currents.red, 0x64);
  EXPECT_EQ(currents.green, 0x87);
  EXPECT_EQ(currents.blue, 0x82);
  dlpc.SetStandby(false);
  EXPECT_EQ(dlpc.GetVersion().ApplicationString(), "4.3.0");

  try {
    dlpc.SetDisplayMode(Dlpc350DisplayMode::kPatternSequence);
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("DLPC350 USB 001/002 (0451:6401): DISP_MODE (0x1A1B)"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("NACK"), std::string::npos) << message;
  }

  // The script has no reply with sequence 8; the replayer hands back earlier replies, which the
  // driver discards by sequence number until its timeout.
  const auto start = std::chrono::steady_clock::now();
  try {
    dlpc.IsStandby();
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("no reply to POWER_CONTROL (0x0200) read within 200 ms "
                                         "(2 attempts)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

TEST(Dlpc350UsbReplayTest, BytesThatDifferFromTheScriptFailTheTransfer) {
  Dlpc350 dlpc(std::make_unique<LibusbDlpc350Transport>(UnderUmockdev()), FastTimeouts());
  // Sequence 0 with these currents is not in the script: umockdev rejects the OUT URB.
  try {
    dlpc.SetLedCurrents({1, 2, 3});
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("writing a report failed (LIBUSB_ERROR_IO"),
              std::string::npos)
        << e.what();
  }
}

TEST(Dlpc350UsbReplayTest, FindsTheDeviceByBusAndAddressAndNamesMissingOnes) {
  Dlpc350UsbOptions by_position = UnderUmockdev();
  by_position.bus = 1;
  by_position.address = 2;
  EXPECT_EQ(LibusbDlpc350Transport(by_position).Name(), "DLPC350 USB 001/002 (0451:6401)");

  by_position.address = 9;
  EXPECT_THROW(LibusbDlpc350Transport transport(by_position), DeviceError);

  Dlpc350UsbOptions other = UnderUmockdev();
  other.product_id = 0x6402;
  try {
    LibusbDlpc350Transport transport(other);
    FAIL() << "no exception";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("DLPC350 USB 0451:6402: not found"), std::string::npos)
        << e.what();
  }
  const auto devices = ListUsbDevices(0x0451, 0x6401);
  ASSERT_EQ(devices.size(), 1u);
  EXPECT_EQ(devices[0].bus, 1);
  EXPECT_EQ(devices[0].address, 2);
}

}  // namespace
}  // namespace zbrdf
