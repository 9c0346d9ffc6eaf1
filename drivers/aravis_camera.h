// GigE Vision cameras through Aravis 0.8, opened by IP address without device discovery.
//
// Why no discovery: Aravis's device list (arv_update_device_list, arv_open_device(NULL), opening
// by name) broadcasts GVCP discovery packets on every network interface. In this workplace that
// is allowed only behind an explicit user command (`zbrdf devices`, see DiscoverCameras()). The
// driver therefore talks to exactly one address with arv_gv_device_new(interface, device), and a
// camera known only by its serial number is resolved through the camera directory that
// `zbrdf devices --save` writes (no broadcast at open time).
//
// What the driver does at open: selects the pixel format (and checks it can unpack it), turns
// ExposureAuto, GainAuto and BalanceWhiteAuto off where present, applies the gain (Gain in dB or
// GainRaw) and region, sets continuous acquisition with TriggerMode=On (FrameStart), and creates
// a stream with a pool of `buffers` frame buffers.
//
// Grab() in TriggerMode::kSoftware fires TriggerSoftware and waits for that frame. A frame whose
// buffer status is not ARV_BUFFER_STATUS_SUCCESS (missing packets, a timeout inside the stream,
// a size mismatch) is never returned: the driver triggers again, at most `retries` times, and
// then throws DeviceError. In TriggerMode::kHardwareLine the camera waits for a rising edge on
// `trigger_line` (the projector's trigger output); Grab() drops frames already queued or exposed
// before the call and returns the next complete frame (see docs/hardware-rig.md, "Sync").
//
// Errors are DeviceError (camera failed, stopped answering, timed out) or InputError (the rig
// file asks for something the camera does not offer); every message names the camera
// ("camera 192.0.2.10 (Basler acA1300, serial 2233)") and the GenICam feature.
//
// Timing of failures: Aravis 0.8 waits 5 x 500 ms for a GVCP acknowledge (compiled in), so a
// camera that stopped answering makes the next command (and hence Grab) fail after about 2.5 s.
// Destroying the driver stops acquisition and frees the stream also after an exception; for a
// camera that is gone this costs another GVCP timeout while Aravis releases control.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "drivers/camera.h"
#include "drivers/clock.h"
#include "drivers/pixel_format.h"

namespace zbrdf {

struct AravisCameraOptions {
  // The camera's IPv4 address (dotted quad). Required unless `serial` resolves through the
  // camera directory. 127.0.0.1 reaches an Aravis fake camera (drivers/fake_gige_camera.h).
  std::string ip;
  // Alternatively (or additionally, as a check) the camera's serial number.
  std::string serial;
  // The local interface address the camera is reached through; empty: ask the kernel's routing
  // table (a connect() on a UDP socket, which sends nothing).
  std::string interface_ip;
  // Camera directory for `serial` lookups; empty: DefaultCameraDirectoryPath().
  std::string camera_directory;

  // GenICam PixelFormat name ("BayerRG12", "Mono16", ...); empty: the deepest format in
  // SupportedPixelFormats() the camera offers.
  std::string pixel_format;
  // Analog gain in the camera's unit (dB for "Gain", raw counts for "GainRaw"); unset: leave.
  std::optional<double> gain;
  // Exposure limits the rig allows (microseconds); SetExposure outside them throws. The camera's
  // own limits apply as well; CameraInfo reports the intersection.
  double exposure_min_us = 0;
  double exposure_max_us = 1e12;
  // Initial exposure; unset: leave the camera's current value.
  std::optional<double> exposure_us;

  // Region of interest; 0 width/height: the camera's current region.
  int region_x = 0, region_y = 0, region_width = 0, region_height = 0;

  TriggerMode trigger_mode = TriggerMode::kSoftware;
  std::string trigger_line = "Line0";  // TriggerSource for kHardwareLine

  int retries = 3;            // re-captures of a frame with missing data (per Grab)
  int buffers = 4;            // stream buffer pool size
  int packet_size = 0;        // GevSCPSPacketSize in bytes; 0: leave the camera's value
  bool packet_resend = true;  // ask the camera to resend lost packets
  // Aravis stream tuning (microseconds): how long an incomplete frame is kept waiting for its
  // packets, and the gap between packets that counts as a loss. 0: Aravis's defaults.
  int frame_retention_us = 0;
  int packet_timeout_us = 0;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

// Counters since open; a session can log them and check-rig prints them.
struct AravisCameraStats {
  uint64_t frames = 0;             // frames returned by Grab
  uint64_t incomplete_frames = 0;  // frames dropped because data were missing
  uint64_t timeouts = 0;           // triggers that brought no frame within the timeout
  uint64_t stale_frames = 0;       // hardware-trigger frames exposed before Grab was called
};

class AravisCamera final : public Camera {
 public:
  // Opens the camera (see the file comment). `clock` timestamps frames; it must outlive the
  // camera; nullptr: an internal SteadyClock.
  explicit AravisCamera(const AravisCameraOptions& options, Clock* clock = nullptr);
  ~AravisCamera() override;
  AravisCamera(const AravisCamera&) = delete;
  AravisCamera& operator=(const AravisCamera&) = delete;

  CameraInfo Info() const override;
  double SetExposure(double exposure_us) override;
  void SetTriggerMode(TriggerMode mode) override;
  // `timeout` bounds each attempt (trigger to frame); with retries the call can take up to
  // (retries + 1) x timeout, plus ~2.5 s if the camera stopped answering.
  Frame Grab(std::chrono::milliseconds timeout) override;

  // Sets the analog gain in the camera's unit (CameraInfo::gain_unit); returns the value used.
  double SetGain(double gain);
  std::string PixelFormatName() const;
  std::string SerialNumber() const;
  AravisCameraStats Stats() const;
  // "camera 127.0.0.1 (Aravis Fake, serial GV01)": the prefix of every error message.
  std::string Describe() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The local IPv4 address the kernel would use to reach `remote_ip` (UDP connect + getsockname;
// no packet is sent). Throws InputError for a malformed address, DeviceError if unroutable.
std::string LocalInterfaceFor(const std::string& remote_ip);

// ---- Camera directory: serial -> IP, written by `zbrdf devices --save` ----

struct CameraDirectoryEntry {
  std::string serial;
  std::string ip;
  std::string vendor;
  std::string model;
};

// $XDG_CACHE_HOME/zbrdf/cameras.yaml, or ~/.cache/zbrdf/cameras.yaml.
std::string DefaultCameraDirectoryPath();
// Missing file: empty list. Malformed file: InputError naming it.
std::vector<CameraDirectoryEntry> ReadCameraDirectory(const std::string& path);
// Replaces entries with the same serial, keeps the others; creates the folder.
void WriteCameraDirectory(const std::string& path, const std::vector<CameraDirectoryEntry>& seen);

// ---- Discovery: BROADCASTS on every interface. Only `zbrdf devices` may call this. ----

struct DiscoveredCamera {
  std::string id;        // Aravis device id
  std::string protocol;  // "GigEVision", "USB3Vision", "Fake"
  std::string address;   // IP address for GigE Vision
  std::string vendor;
  std::string model;
  std::string serial;
};

// Runs Aravis device discovery (arv_update_device_list): sends GVCP discovery broadcasts on
// every network interface and enumerates USB3 Vision devices. Never call this from tests, CI,
// examples or library code paths; it exists for the explicit `zbrdf devices` command.
std::vector<DiscoveredCamera> DiscoverCamerasByBroadcast();

}  // namespace zbrdf
