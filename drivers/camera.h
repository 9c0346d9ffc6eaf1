// The camera interface a capture session runs against.
//
// Implemented by the Aravis driver (drivers/aravis_camera.h) for GigE Vision / USB3 Vision
// cameras and by the simulator's virtual camera (simulate/virtual_rig.h). A session only ever
// sees this interface, so a capture runs the same on hardware and on the simulated rig.
//
// Frames are raw sensor values: a Bayer mosaic or mono image, one uint16 sample per pixel
// holding the sensor's `bit_depth` significant bits (a 12-bit sensor gives 0..4095), or three
// interleaved samples per pixel for PixelLayout::kRgb. No demosaicing, no black-level removal.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace zbrdf {

enum class PixelLayout { kMono, kBayerRGGB, kBayerGRBG, kBayerGBRG, kBayerBGGR, kRgb };

// "mono", "bayer-rggb", ... as used in rig files and session.json.
std::string PixelLayoutName(PixelLayout layout);
// Inverse of PixelLayoutName; throws InputError naming the accepted values.
PixelLayout ParsePixelLayout(const std::string& name);
// Samples per pixel: 3 for kRgb, else 1.
inline int SamplesPerPixel(PixelLayout layout) { return layout == PixelLayout::kRgb ? 3 : 1; }

// True for a dotted-quad IPv4 address such as "192.0.2.10" (how cameras are addressed: by IP,
// never by discovery).
bool IsIpv4Address(const std::string& text);

struct Frame {
  int width = 0;
  int height = 0;
  PixelLayout layout = PixelLayout::kMono;
  int bit_depth = 12;          // significant bits per sample
  std::vector<uint16_t> data;  // row-major, width * height * SamplesPerPixel(layout) samples
  double exposure_us = 0;      // exposure the camera actually used
  double gain = 1;             // analog gain in the camera's own unit (see CameraInfo)
  uint64_t frame_id = 0;       // camera's frame counter
  int64_t timestamp_us = 0;    // when the exposure started, on the session's clock
};

enum class TriggerMode {
  kSoftware,      // Grab() fires a software trigger, then waits for the frame
  kHardwareLine,  // Grab() waits for a frame triggered on the camera's input line
};

struct CameraInfo {
  std::string id;      // what the camera was opened by: IP address, serial, or "virtual"
  std::string model;   // vendor and model
  int width = 0;
  int height = 0;
  PixelLayout layout = PixelLayout::kMono;
  int bit_depth = 12;
  double min_exposure_us = 0;
  double max_exposure_us = 0;
  std::string gain_unit;  // "dB", "raw", or "e-/DN" for the virtual camera
};

class Camera {
 public:
  virtual ~Camera() = default;

  virtual CameraInfo Info() const = 0;

  // Sets the exposure time; returns the value the camera actually uses (cameras quantize it).
  // Throws DeviceError if the camera rejects it (the message names the camera and feature).
  virtual double SetExposure(double exposure_us) = 0;

  virtual void SetTriggerMode(TriggerMode mode) = 0;

  // The capture plan's index of the next frame. Hardware drivers may ignore it (or log it); the
  // simulator's virtual camera keys its noise on it, so that a resumed capture reproduces an
  // uninterrupted one frame for frame.
  virtual void SetNextFrameIndex(uint64_t index) { (void)index; }

  // Captures one frame (see TriggerMode). Throws DeviceError on timeout, on a frame with
  // missing data after the driver's retries, or if the camera stopped answering.
  virtual Frame Grab(std::chrono::milliseconds timeout) = 0;
};

}  // namespace zbrdf
