// The projector interface a capture session runs against.
//
// Implemented by the HDMI display driver (drivers/x11_display.h, optionally with DLPC350 USB
// control) and by the simulator's virtual projector (simulate/virtual_rig.h).
//
// A pattern is a gray-level image at the projector's native resolution: one value per pixel in
// 0 .. 2^bit_depth - 1, shown on all color channels (the illumination is white).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace zbrdf {

struct Pattern {
  int width = 0;
  int height = 0;
  int bit_depth = 8;
  std::vector<uint16_t> levels;  // row-major, width * height
};

struct ProjectorInfo {
  std::string id;     // X11 output name, USB path, or "virtual"
  std::string model;
  int width = 0;
  int height = 0;
  int bit_depth = 8;
};

class Projector {
 public:
  virtual ~Projector() = default;

  virtual ProjectorInfo Info() const = 0;

  // Displays the pattern and returns once it is on screen (after vsync where the display
  // supports it). The caller still waits the rig's settle time before exposing.
  // Throws InputError for a pattern of the wrong size or depth, DeviceError on device failure.
  virtual void Show(const Pattern& pattern) = 0;

  // How many patterns ahead this projector can use (Upcoming); 0, the default: none.
  virtual int PatternsAhead() const { return 0; }
  // The patterns the caller means to Show next, in order, the first being the next Show: a
  // hint, so the caller may still show others or fewer. The virtual projector has them all
  // rendered in one pass over its light transport when the first is shown (a frame is the same
  // either way, bit for bit); a hardware driver could upload them ahead. Default: ignored.
  virtual void Upcoming(std::span<const Pattern> patterns) { (void)patterns; }
};

}  // namespace zbrdf
