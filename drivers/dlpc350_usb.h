// The DLPC350 HID transport over libusb: interrupt transfers on endpoints 0x01 / 0x81 of
// interface 0.
//
// The projector is found by USB bus number and device address (as `lsusb` prints them) or by
// VID:PID (first match). USB enumeration is local to this machine; nothing goes on a network.
//
// Kernel driver: on Linux the usbhid driver binds the DLPC350's HID interface, so claiming it
// needs the driver detached. `auto_detach_kernel_driver` (default true, right for real
// hardware) asks libusb to detach it on claim and re-attach it on release. Under umockdev, which
// emulates usbdevfs but not the driver (dis)connect ioctls, it must be false; the tests set it so.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "drivers/dlpc350.h"

namespace zbrdf {

struct Dlpc350UsbOptions {
  uint16_t vendor_id = 0x0451;
  uint16_t product_id = 0x6401;
  // Both >= 0: open the device at this bus and address instead of the first VID:PID match.
  int bus = -1;
  int address = -1;
  int interface_number = 0;
  uint8_t out_endpoint = 0x01;
  uint8_t in_endpoint = 0x81;
  bool auto_detach_kernel_driver = true;
};

class LibusbDlpc350Transport final : public Dlpc350Transport {
 public:
  // Opens and claims the interface; throws DeviceError naming the device and what to do
  // (permissions: a udev rule for 0451:6401; busy: another program holds it).
  explicit LibusbDlpc350Transport(const Dlpc350UsbOptions& options = {});
  ~LibusbDlpc350Transport() override;
  LibusbDlpc350Transport(const LibusbDlpc350Transport&) = delete;
  LibusbDlpc350Transport& operator=(const LibusbDlpc350Transport&) = delete;

  std::string Name() const override { return name_; }
  void Write(const Dlpc350Report& report, std::chrono::milliseconds timeout) override;
  bool Read(Dlpc350Report* report, std::chrono::milliseconds timeout) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string name_;
};

struct UsbDeviceSummary {
  int bus = 0;
  int address = 0;
  uint16_t vendor_id = 0;
  uint16_t product_id = 0;
};

// USB devices with the given VID:PID on this machine (local enumeration, no network).
std::vector<UsbDeviceSummary> ListUsbDevices(uint16_t vendor_id, uint16_t product_id);

}  // namespace zbrdf
