// The hardware rig file: which camera, which projector, how they are synchronized.
//
// A YAML file (docs/hardware-rig.md documents every field; docs/examples/lab-rig.yaml is an
// example) with three sections:
//   camera:     ip or serial, pixel format, gain, exposure limits, timeout, retries, ...
//   projector:  the X11 output the projector is, optional DLPC350 USB control, LED currents
//   sync:       hardware | software, settle times
// LoadHardwareRig validates the whole file and reports every problem at once, each naming the
// file and field: "rig file lab.yaml: camera.ip '300.1.2.3' is not an IPv4 address".
// Unknown keys are errors too (a misspelt key would otherwise be silently ignored).
//
// The factories open the devices a rig describes; they never run network discovery (a camera
// given only by serial is resolved through the camera directory, see drivers/aravis_camera.h).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "drivers/aravis_camera.h"
#include "drivers/dlpc350.h"
#include "drivers/dlpc350_usb.h"
#include "drivers/rig_sync.h"
#include "drivers/x11_display.h"

namespace zbrdf {

struct RigCameraConfig {
  std::string ip;
  std::string serial;
  std::string interface_ip;
  std::string pixel_format;
  std::optional<double> gain;
  double exposure_min_us = 10;
  double exposure_max_us = 10e6;
  double check_exposure_us = 10000;  // exposure `zbrdf check-rig` uses
  int timeout_ms = 2000;             // per Grab attempt
  int retries = 3;
  int buffers = 4;
  int packet_size = 0;
  std::string trigger_line = "Line0";
  int region_x = 0, region_y = 0, region_width = 0, region_height = 0;
};

struct RigProjectorConfig {
  std::string x11_display;  // empty: $DISPLAY
  std::string x11_output;   // required, e.g. "HDMI-1"
  double refresh_hz = 0;
  int settle_frames = 2;
  // DLPC350 USB control (optional).
  bool usb = false;
  int usb_bus = -1;
  int usb_address = -1;
  uint16_t usb_vendor_id = 0x0451;
  uint16_t usb_product_id = 0x6401;
  bool usb_auto_detach_kernel_driver = true;
  std::optional<Dlpc350LedCurrents> led_currents;
  int trigger_output = 1;  // DLPC350 TRIG_OUT wired to the camera (hardware sync)
};

struct HardwareRig {
  std::string source;  // file name, for messages
  RigCameraConfig camera;
  RigProjectorConfig projector;
  RigSyncConfig sync;
};

// Throws InputError listing every problem ("rig file X: field: problem; ...").
HardwareRig LoadHardwareRig(const std::string& path);
HardwareRig ParseHardwareRig(const std::string& yaml_text, const std::string& source_name);

AravisCameraOptions CameraOptionsFromRig(const HardwareRig& rig);

// The rig's projector: the X11 display that shows the patterns, plus USB control of a DLPC350
// when the rig file has projector.usb. Show() draws on the display; control() reaches the
// controller (status, LEDs, trigger outputs).
class RigProjector final : public Projector {
 public:
  RigProjector(std::unique_ptr<X11Display> display, std::unique_ptr<Dlpc350> control);
  ProjectorInfo Info() const override;
  void Show(const Pattern& pattern) override;
  X11Display& display() { return *display_; }
  Dlpc350* control() { return control_.get(); }

 private:
  std::unique_ptr<X11Display> display_;
  std::unique_ptr<Dlpc350> control_;
};

// Opens the camera in the trigger mode the rig's sync mode needs.
std::unique_ptr<AravisCamera> OpenRigCamera(const HardwareRig& rig, Clock* clock = nullptr);

// Opens the display and, if configured, the DLPC350: wakes it from standby, selects video mode
// with the 24-bit parallel (HDMI) input, sets the LED currents, and configures the trigger
// output used for hardware sync.
std::unique_ptr<RigProjector> OpenRigProjector(const HardwareRig& rig);

// Applies the rig's video-mode setup to a DLPC350 (what OpenRigProjector does over USB); exposed
// so that it is testable against the emulator.
void ConfigureDlpc350ForVideo(Dlpc350& control, const RigProjectorConfig& config, SyncMode sync);

}  // namespace zbrdf
