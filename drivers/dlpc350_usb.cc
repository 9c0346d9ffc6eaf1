#include "drivers/dlpc350_usb.h"

#include <libusb-1.0/libusb.h>

#include <algorithm>
#include <cstdio>

#include "basis/error.h"

namespace zbrdf {

namespace {

std::string UsbName(int bus, int address, uint16_t vid, uint16_t pid) {
  char text[64];
  std::snprintf(text, sizeof(text), "DLPC350 USB %03d/%03d (%04x:%04x)", bus, address, vid, pid);
  return text;
}

std::string ErrorText(int code) {
  return std::string(libusb_error_name(code)) + ": " + libusb_strerror(code);
}

}  // namespace

struct LibusbDlpc350Transport::Impl {
  libusb_context* context = nullptr;
  libusb_device_handle* handle = nullptr;
  bool claimed = false;
  Dlpc350UsbOptions options;

  ~Impl() {
    if (handle != nullptr) {
      if (claimed) libusb_release_interface(handle, options.interface_number);
      libusb_close(handle);
    }
    if (context != nullptr) libusb_exit(context);
  }
};

LibusbDlpc350Transport::LibusbDlpc350Transport(const Dlpc350UsbOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  char wanted[32];
  std::snprintf(wanted, sizeof(wanted), "%04x:%04x", options.vendor_id, options.product_id);
  name_ = std::string("DLPC350 USB ") + wanted;
  int rc = libusb_init(&impl_->context);
  if (rc != 0) throw DeviceError(name_ + ": libusb_init failed (" + ErrorText(rc) + ")");

  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(impl_->context, &list);
  if (n < 0) {
    throw DeviceError(name_ + ": cannot list USB devices (" + ErrorText(static_cast<int>(n)) + ")");
  }
  libusb_device* found = nullptr;
  for (ssize_t i = 0; i < n && found == nullptr; ++i) {
    libusb_device_descriptor descriptor{};
    if (libusb_get_device_descriptor(list[i], &descriptor) != 0) continue;
    const int bus = libusb_get_bus_number(list[i]);
    const int address = libusb_get_device_address(list[i]);
    const bool by_position = options.bus >= 0 && options.address >= 0;
    if (by_position ? (bus == options.bus && address == options.address)
                    : (descriptor.idVendor == options.vendor_id &&
                       descriptor.idProduct == options.product_id)) {
      if (descriptor.idVendor != options.vendor_id || descriptor.idProduct != options.product_id) {
        libusb_free_device_list(list, 1);
        char got[16];
        std::snprintf(got, sizeof(got), "%04x:%04x", descriptor.idVendor, descriptor.idProduct);
        throw DeviceError(UsbName(bus, address, options.vendor_id, options.product_id) +
                          ": the device at this bus/address is " + got +
                          ", not a DLPC350; check projector.usb.bus/address (lsusb lists them)");
      }
      found = list[i];
      name_ = UsbName(bus, address, descriptor.idVendor, descriptor.idProduct);
    }
  }
  if (found == nullptr) {
    libusb_free_device_list(list, 1);
    throw DeviceError(name_ +
                      (options.bus >= 0 ? " at bus " + std::to_string(options.bus) + " address " +
                                              std::to_string(options.address)
                                        : std::string()) +
                      ": not found; check that the projector is on and its USB cable plugged in "
                      "(lsusb should list it)");
  }
  rc = libusb_open(found, &impl_->handle);
  libusb_free_device_list(list, 1);
  if (rc != 0) {
    throw DeviceError(name_ + ": cannot open (" + ErrorText(rc) + ")" +
                      (rc == LIBUSB_ERROR_ACCESS
                           ? "; add a udev rule giving your user access to 0451:6401"
                           : ""));
  }
  if (options.auto_detach_kernel_driver) {
    rc = libusb_set_auto_detach_kernel_driver(impl_->handle, 1);
    if (rc != 0 && rc != LIBUSB_ERROR_NOT_SUPPORTED) {
      throw DeviceError(name_ + ": cannot enable kernel driver auto-detach (" + ErrorText(rc) +
                        ")");
    }
  }
  rc = libusb_claim_interface(impl_->handle, options.interface_number);
  if (rc != 0) {
    throw DeviceError(name_ + ": cannot claim interface " +
                      std::to_string(options.interface_number) + " (" + ErrorText(rc) + ")" +
                      (rc == LIBUSB_ERROR_BUSY
                           ? "; another program (or the usbhid driver, if auto-detach is off) "
                             "holds it"
                           : ""));
  }
  impl_->claimed = true;
}

LibusbDlpc350Transport::~LibusbDlpc350Transport() = default;

void LibusbDlpc350Transport::Write(const Dlpc350Report& report, std::chrono::milliseconds timeout) {
  Dlpc350Report buffer = report;
  int transferred = 0;
  const int rc = libusb_interrupt_transfer(impl_->handle, impl_->options.out_endpoint,
                                           buffer.data(), static_cast<int>(buffer.size()),
                                           &transferred, static_cast<unsigned>(timeout.count()));
  if (rc == LIBUSB_ERROR_TIMEOUT) {
    throw DeviceError(name_ + ": writing a report timed out after " +
                      std::to_string(timeout.count()) + " ms; is the projector powered?");
  }
  if (rc != 0) {
    throw DeviceError(name_ + ": writing a report failed (" + ErrorText(rc) +
                      "); check the USB connection");
  }
  if (transferred != static_cast<int>(buffer.size())) {
    throw DeviceError(name_ + ": wrote " + std::to_string(transferred) + " of 64 bytes");
  }
}

bool LibusbDlpc350Transport::Read(Dlpc350Report* report, std::chrono::milliseconds timeout) {
  int transferred = 0;
  report->fill(0);
  const unsigned timeout_ms = static_cast<unsigned>(std::max<int64_t>(1, timeout.count()));
  const int rc =
      libusb_interrupt_transfer(impl_->handle, impl_->options.in_endpoint, report->data(),
                                static_cast<int>(report->size()), &transferred, timeout_ms);
  if (rc == LIBUSB_ERROR_TIMEOUT) return false;
  if (rc != 0) {
    throw DeviceError(name_ + ": reading a report failed (" + ErrorText(rc) +
                      "); check the USB connection");
  }
  if (transferred < 4) {
    throw DeviceError(name_ + ": received a " + std::to_string(transferred) +
                      "-byte report, shorter than the 4-byte header");
  }
  return true;
}

std::vector<UsbDeviceSummary> ListUsbDevices(uint16_t vendor_id, uint16_t product_id) {
  std::vector<UsbDeviceSummary> devices;
  libusb_context* context = nullptr;
  if (libusb_init(&context) != 0) return devices;
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(context, &list);
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor descriptor{};
    if (libusb_get_device_descriptor(list[i], &descriptor) != 0) continue;
    if (descriptor.idVendor != vendor_id || descriptor.idProduct != product_id) continue;
    devices.push_back({libusb_get_bus_number(list[i]), libusb_get_device_address(list[i]),
                       descriptor.idVendor, descriptor.idProduct});
  }
  if (n >= 0) libusb_free_device_list(list, 1);
  libusb_exit(context);
  return devices;
}

}  // namespace zbrdf
