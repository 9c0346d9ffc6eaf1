// An Aravis GigE Vision fake camera served from this process on 127.0.0.1.
//
// Tests, demos and simulated captures use it to drive AravisCamera through the real GVCP/GVSP
// stack without hardware and without leaving the loopback interface. It wraps
// arv_gv_fake_camera_new_full() and adds two things the stock fake lacks:
//   - frames chosen per trigger: a FakeFrameSource callback fills each frame with samples of the
//     current pixel format (uint16, `bit_depth` significant bits), which are packed into the
//     GVSP payload exactly as a camera would (drivers/pixel_format.h);
//   - 12- and 16-bit formats: the fake's GenICam description (taken from Aravis at run time) is
//     extended with Mono12, Mono12Packed, Mono12p, BayerRG12, BayerRG12Packed, BayerRG12p,
//     BayerRG16, BayerGB16 and BGR8 entries, so Bayer16 captures can run end to end.
// The fake honours TriggerMode=On with TriggerSource=Software; in Line0 mode it sends nothing
// (there is no line to pulse), which is how tests exercise the hardware-trigger timeout.
//
// Only one fake can listen on 127.0.0.1:3956 at a time (GVCP's port); CTest runs the tests that
// use it under RESOURCE_LOCK zbrdf_gige_fake_3956 (tests/drivers/CMakeLists.txt).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "drivers/camera.h"

namespace zbrdf {

struct FakeFrameRequest {
  uint64_t index = 0;  // 0 for the first frame this source fills, then 1, 2, ...
  int width = 0;
  int height = 0;
  std::string pixel_format;  // GenICam name, e.g. "BayerRG16"
  PixelLayout layout = PixelLayout::kMono;
  int bit_depth = 8;
  double exposure_us = 0;  // the camera's ExposureTimeAbs when the frame was made
  int gain_raw = 0;        // the camera's GainRaw
};

// Fills width * height * SamplesPerPixel(layout) samples, each < 2^bit_depth. Called on the fake
// camera's thread, once per frame sent, with the fixture's lock held: it must be thread-safe with
// respect to the caller's data and must not call back into the FakeGigECamera. Exceptions are
// caught; the frame is then sent as zeros and LastSourceError() reports why.
using FakeFrameSource = std::function<void(const FakeFrameRequest&, std::vector<uint16_t>*)>;

struct FakeGigECameraOptions {
  std::string serial = "ZBRDF-FAKE";
  bool extra_pixel_formats = true;  // add the 12/16-bit entries listed above
  // How often the fake checks for a software trigger (Hz); a frame follows its trigger within
  // 1 / rate. While it streams, Aravis's fake (0.8) polls its sockets with a zero timeout during
  // the last millisecond before each check, so a core spins for min(1, rate / 1000 Hz) of the
  // time: at 1000 Hz the whole capture (measured: 15 of a GigE test's 21 s of CPU).
  double trigger_rate_hz = 250;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

class FakeGigECamera {
 public:
  static constexpr const char* kAddress = "127.0.0.1";

  // Starts listening on 127.0.0.1:3956. Throws DeviceError if the port is taken.
  explicit FakeGigECamera(const FakeGigECameraOptions& options = {});
  ~FakeGigECamera();
  FakeGigECamera(const FakeGigECamera&) = delete;
  FakeGigECamera& operator=(const FakeGigECamera&) = delete;

  // nullptr restores Aravis's built-in pattern (a diagonal ramp for Mono8/Mono16 whose scale
  // follows exposure and gain; see arvfakecamera.c).
  void SetFrameSource(FakeFrameSource source);
  // Probability that each GVSP packet (leader, data, trailer) is dropped, 0..1. The fake never
  // resends a dropped packet. The drops come from GLib's global random generator, seeded with
  // `seed` here: the same packets are dropped on every run, as far as the frames' timing (a
  // frame triggered again after a late one) leaves the sequence of packets the same.
  void SetLostPacketRatio(double ratio, uint32_t seed = 1);
  // Stops answering GVCP and sending GVSP, as a camera that lost power. Idempotent.
  void Stop();

  // The fake's registers (big-endian 32-bit, addresses from its GenICam description, e.g. 0x300
  // TriggerMode, 0x304 TriggerSource, 0x114 GainAuto): lets tests check what a driver wrote and
  // preset what it must change.
  uint32_t ReadRegister(uint32_t address) const;
  void WriteRegister(uint32_t address, uint32_t value);

  std::string Serial() const;
  uint64_t FramesFilled() const;        // frames filled by the FakeFrameSource
  std::string LastSourceError() const;  // empty if every fill succeeded

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace zbrdf
