// The projector as an X11 display: patterns shown full screen on a named RandR output.
//
// The projector (e.g. a LightCrafter 4500 on HDMI) is a monitor to the X server. The driver
// finds the output by its RandR name ("HDMI-1"; Xvfb's only output is "screen"), takes the
// rectangle of the CRTC driving it, and covers exactly that rectangle with an override-redirect
// window (no window manager decoration or placement, cursor hidden). A pattern's gray levels
// are replicated to R, G and B and sent with XPutImage.
//
// What "on screen" means after Show(): the X server has executed the drawing (XSync returned)
// and then `settle_frames` refresh periods have passed, so the new image has been scanned out
// at least once unless a compositor adds frames of latency. There is no vsync lock (GLX swap
// control is deliberately not used); the rig's settle time (hardware-rig.md, "Sync") absorbs
// the remaining uncertainty. The refresh rate comes from the output's mode timing; where the
// server reports none (Xvfb) `refresh_hz` is used (default 60).
//
// MeasureReadbackLatency() reports the time from sending the image (Show() without its settle
// wait) until XGetImage of the screen returns exactly the pattern: the X server's latency, not
// the projector's light output. On hardware the camera-based measurement of `zbrdf check-rig`
// (sync latency) is the one that counts.
//
// Xlib's default error handlers exit the process; this driver installs handlers that record
// the error instead, and turns it into a DeviceError naming the display and output.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "drivers/projector.h"

namespace zbrdf {

struct X11DisplayOptions {
  std::string display;    // X display name, e.g. ":0"; empty: $DISPLAY
  std::string output;     // RandR output name, e.g. "HDMI-1"
  double refresh_hz = 0;  // 0: from the output's mode, else 60 if the mode has no timing
  int settle_frames = 2;  // refresh periods Show() waits after XSync
  std::string model;      // ProjectorInfo::model; empty: "X11 output <name>"
};

struct X11OutputInfo {
  std::string name;
  bool connected = false;
  bool active = false;  // driven by a CRTC
  int x = 0, y = 0, width = 0, height = 0;
  double refresh_hz = 0;  // 0 if the server reports no mode timing
};

// An RGB screen capture, 8 bits per channel, row-major R, G, B.
struct X11Capture {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;
};

class X11Display final : public Projector {
 public:
  // Opens the display and creates the window on the output. Throws DeviceError if the display
  // cannot be opened, or InputError if the output does not exist or is not active (the message
  // lists the outputs there are).
  explicit X11Display(const X11DisplayOptions& options);
  ~X11Display() override;
  X11Display(const X11Display&) = delete;
  X11Display& operator=(const X11Display&) = delete;

  // bit_depth is 8 (24-bit TrueColor visuals); width/height are the output's.
  ProjectorInfo Info() const override;
  void Show(const Pattern& pattern) override;

  // What the screen shows now over the output's rectangle (XGetImage of the root window).
  X11Capture ReadBack();
  // Sends `pattern` and polls ReadBack() until it matches exactly; returns the time from sending
  // to the first matching read-back. Throws DeviceError on timeout.
  std::chrono::microseconds MeasureReadbackLatency(const Pattern& pattern,
                                                   std::chrono::milliseconds timeout);
  double RefreshHz() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// RandR outputs of a display (empty name: $DISPLAY). Throws DeviceError if it cannot be opened.
std::vector<X11OutputInfo> ListX11Outputs(const std::string& display);

// True if the capture shows `pattern` on all three channels (levels scaled to 8 bits).
bool CaptureMatches(const X11Capture& capture, const Pattern& pattern);

}  // namespace zbrdf
