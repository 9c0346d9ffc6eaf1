// GenICam pixel formats that zbrdf can unpack into a Frame, and the unpacking itself.
//
// A camera delivers a payload in one of the Pixel Format Naming Convention (PFNC) layouts; a
// Frame holds one uint16 per sample with `bit_depth` significant bits (drivers/camera.h). This
// file is the single place that knows how the bytes are laid out:
//   - 8-bit formats (Mono8, Bayer**8, RGB8, BGR8): one byte per sample.
//   - unpacked 10/12/14/16-bit formats (Mono12, BayerRG16, ...): a little-endian uint16 per
//     sample, the value in the low `bit_depth` bits (PFNC; GigE Vision streams are LSB first).
//   - GigE Vision "Packed" 12-bit (Mono12Packed, BayerRG12Packed): two pixels in three bytes,
//       B0 = P0[11:4], B1 = P1[3:0] << 4 | P0[3:0], B2 = P1[11:4]   (GigE Vision 2.0, 4.3.2).
//   - PFNC "p" 12-bit (Mono12p, BayerRG12p): a little-endian bit stream, LSB first,
//       B0 = P0[7:0], B1 = P1[3:0] << 4 | P0[11:8], B2 = P1[11:4]   (PFNC 2.1, "Mono12p").
// BGR8 is reordered to RGB so that PixelLayout::kRgb always means R, G, B.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "drivers/camera.h"

namespace zbrdf {

enum class PixelPacking {
  k8Bit,        // one byte per sample
  k16BitLE,     // little-endian uint16 container
  kGvPacked12,  // GigE Vision Mono12Packed layout (2 pixels in 3 bytes)
  kPfnc12p,     // PFNC Mono12p layout (LSB-first bit stream)
  kBgr8,        // 3 bytes B, G, R; delivered as R, G, B
};

struct PixelFormatInfo {
  const char* name;  // GenICam PixelFormat entry name, e.g. "BayerRG12"
  uint32_t pfnc;     // PFNC / GigE Vision code, e.g. 0x01100011
  PixelLayout layout;
  int bit_depth;  // significant bits per sample
  PixelPacking packing;
};

// The table of formats zbrdf unpacks, in order of preference for a measurement (deepest
// unpacked formats first). Used to pick a default when a rig file names none.
const std::vector<PixelFormatInfo>& SupportedPixelFormats();

// nullptr when the code or name is not one zbrdf can unpack.
const PixelFormatInfo* FindPixelFormat(uint32_t pfnc);
const PixelFormatInfo* FindPixelFormat(const std::string& name);

// Payload bytes of one width x height image in this format.
size_t PayloadBytes(const PixelFormatInfo& format, int width, int height);

// Unpacks `size` bytes into width * height * SamplesPerPixel(format.layout) samples.
// Throws DeviceError naming the format if `size` is smaller than PayloadBytes (a truncated
// frame must never become a Frame). Extra trailing bytes (padding) are ignored.
void UnpackPixels(const PixelFormatInfo& format, const uint8_t* data, size_t size, int width,
                  int height, std::vector<uint16_t>* samples);

// The inverse of UnpackPixels: writes PayloadBytes bytes. Samples above 2^bit_depth - 1 throw
// InputError. Used by the fake camera (drivers/fake_gige_camera.h) to serve chosen images.
void PackPixels(const PixelFormatInfo& format, const std::vector<uint16_t>& samples, int width,
                int height, uint8_t* data);

}  // namespace zbrdf
