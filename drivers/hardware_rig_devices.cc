// The factories of drivers/hardware_rig.h: they open the devices a hardware rig file describes.
// Apart from the file's reader (drivers/hardware_rig.cc) so that what only reads the file (the
// fuzz stage's readers, fuzz/CMakeLists.txt) does not need the drivers of the devices.
#include "drivers/hardware_rig.h"

#include <chrono>
#include <thread>

#include "basis/error.h"

namespace zbrdf {

std::unique_ptr<AravisCamera> OpenRigCamera(const HardwareRig& rig, Clock* clock) {
  return std::make_unique<AravisCamera>(CameraOptionsFromRig(rig), clock);
}

RigProjector::RigProjector(std::unique_ptr<X11Display> display, std::unique_ptr<Dlpc350> control)
    : display_(std::move(display)), control_(std::move(control)) {
  if (!display_) throw InputError("RigProjector needs a display");
}

ProjectorInfo RigProjector::Info() const {
  ProjectorInfo info = display_->Info();
  if (control_) info.model = "DLPC350 (" + control_->Name() + ") on " + info.model;
  return info;
}

void RigProjector::Show(const Pattern& pattern) { display_->Show(pattern); }

void ConfigureDlpc350ForVideo(Dlpc350& control, const RigProjectorConfig& config, SyncMode sync) {
  if (control.IsStandby()) {
    control.SetStandby(false);
    // Leaving standby powers the DMD up, which takes seconds (programmer's guide).
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (control.IsStandby()) {
      if (std::chrono::steady_clock::now() > deadline) {
        throw DeviceError(control.Name() + ": still in standby 10 s after POWER_CONTROL normal");
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
  control.SetDisplayMode(Dlpc350DisplayMode::kVideo);
  // The LightCrafter 4500's HDMI receiver feeds the DLPC350's 24-bit parallel port.
  control.SetInputSource(Dlpc350InputSource::kParallel, Dlpc350PortWidth::k24);
  control.SetLedEnables(Dlpc350LedEnables{});
  if (config.led_currents) control.SetLedCurrents(*config.led_currents);
  if (sync == SyncMode::kHardware) {
    const Dlpc350TriggerOut trigger;  // active high, no delay
    if (config.trigger_output == 1) {
      control.SetTriggerOut1(trigger);
    } else {
      control.SetTriggerOut2(trigger);
    }
  }
  const Dlpc350Status status = control.GetStatus();
  if (!status.Problems().empty()) {
    throw DeviceError(control.Name() + ": controller reports: " + status.Problems());
  }
}

std::unique_ptr<RigProjector> OpenRigProjector(const HardwareRig& rig) {
  X11DisplayOptions display_options;
  display_options.display = rig.projector.x11_display;
  display_options.output = rig.projector.x11_output;
  display_options.refresh_hz = rig.projector.refresh_hz;
  display_options.settle_frames = rig.projector.settle_frames;
  auto display = std::make_unique<X11Display>(display_options);
  std::unique_ptr<Dlpc350> control;
  if (rig.projector.usb) {
    Dlpc350UsbOptions usb;
    usb.vendor_id = rig.projector.usb_vendor_id;
    usb.product_id = rig.projector.usb_product_id;
    usb.bus = rig.projector.usb_bus;
    usb.address = rig.projector.usb_address;
    usb.auto_detach_kernel_driver = rig.projector.usb_auto_detach_kernel_driver;
    control = std::make_unique<Dlpc350>(std::make_unique<LibusbDlpc350Transport>(usb));
    ConfigureDlpc350ForVideo(*control, rig.projector, rig.sync.mode);
  }
  return std::make_unique<RigProjector>(std::move(display), std::move(control));
}

}  // namespace zbrdf
