#include "drivers/pixel_format.h"

#include <cstring>

#include "basis/error.h"

namespace zbrdf {

namespace {

using L = PixelLayout;
using P = PixelPacking;

// Codes from the PFNC (as in Aravis's arvenums.h). Order = preference for a default choice.
const std::vector<PixelFormatInfo> kFormats = {
    {"Mono12", 0x01100005, L::kMono, 12, P::k16BitLE},
    {"BayerRG12", 0x01100011, L::kBayerRGGB, 12, P::k16BitLE},
    {"BayerGR12", 0x01100010, L::kBayerGRBG, 12, P::k16BitLE},
    {"BayerGB12", 0x01100012, L::kBayerGBRG, 12, P::k16BitLE},
    {"BayerBG12", 0x01100013, L::kBayerBGGR, 12, P::k16BitLE},
    {"Mono14", 0x01100025, L::kMono, 14, P::k16BitLE},
    {"Mono16", 0x01100007, L::kMono, 16, P::k16BitLE},
    {"BayerRG16", 0x0110002f, L::kBayerRGGB, 16, P::k16BitLE},
    {"BayerGR16", 0x0110002e, L::kBayerGRBG, 16, P::k16BitLE},
    {"BayerGB16", 0x01100030, L::kBayerGBRG, 16, P::k16BitLE},
    {"BayerBG16", 0x01100031, L::kBayerBGGR, 16, P::k16BitLE},
    {"Mono12Packed", 0x010c0006, L::kMono, 12, P::kGvPacked12},
    {"BayerRG12Packed", 0x010c002b, L::kBayerRGGB, 12, P::kGvPacked12},
    {"BayerGR12Packed", 0x010c002a, L::kBayerGRBG, 12, P::kGvPacked12},
    {"BayerGB12Packed", 0x010c002c, L::kBayerGBRG, 12, P::kGvPacked12},
    {"BayerBG12Packed", 0x010c002d, L::kBayerBGGR, 12, P::kGvPacked12},
    {"Mono12p", 0x010c0047, L::kMono, 12, P::kPfnc12p},
    {"BayerRG12p", 0x010c0059, L::kBayerRGGB, 12, P::kPfnc12p},
    {"BayerGR12p", 0x010c0057, L::kBayerGRBG, 12, P::kPfnc12p},
    {"BayerGB12p", 0x010c0055, L::kBayerGBRG, 12, P::kPfnc12p},
    {"BayerBG12p", 0x010c0053, L::kBayerBGGR, 12, P::kPfnc12p},
    {"Mono10", 0x01100003, L::kMono, 10, P::k16BitLE},
    {"BayerRG10", 0x0110000d, L::kBayerRGGB, 10, P::k16BitLE},
    {"BayerGR10", 0x0110000c, L::kBayerGRBG, 10, P::k16BitLE},
    {"BayerGB10", 0x0110000e, L::kBayerGBRG, 10, P::k16BitLE},
    {"BayerBG10", 0x0110000f, L::kBayerBGGR, 10, P::k16BitLE},
    {"Mono8", 0x01080001, L::kMono, 8, P::k8Bit},
    {"BayerRG8", 0x01080009, L::kBayerRGGB, 8, P::k8Bit},
    {"BayerGR8", 0x01080008, L::kBayerGRBG, 8, P::k8Bit},
    {"BayerGB8", 0x0108000a, L::kBayerGBRG, 8, P::k8Bit},
    {"BayerBG8", 0x0108000b, L::kBayerBGGR, 8, P::k8Bit},
    {"RGB8", 0x02180014, L::kRgb, 8, P::k8Bit},
    {"BGR8", 0x02180015, L::kRgb, 8, P::kBgr8},
};

}  // namespace

const std::vector<PixelFormatInfo>& SupportedPixelFormats() { return kFormats; }

const PixelFormatInfo* FindPixelFormat(uint32_t pfnc) {
  for (const auto& f : kFormats) {
    if (f.pfnc == pfnc) return &f;
  }
  return nullptr;
}

const PixelFormatInfo* FindPixelFormat(const std::string& name) {
  for (const auto& f : kFormats) {
    if (name == f.name) return &f;
  }
  return nullptr;
}

size_t PayloadBytes(const PixelFormatInfo& format, int width, int height) {
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  switch (format.packing) {
    case PixelPacking::k8Bit:
      return pixels * static_cast<size_t>(SamplesPerPixel(format.layout));
    case PixelPacking::kBgr8:
      return pixels * 3;
    case PixelPacking::k16BitLE:
      return pixels * 2 * static_cast<size_t>(SamplesPerPixel(format.layout));
    case PixelPacking::kGvPacked12:
    case PixelPacking::kPfnc12p:
      return (pixels * 12 + 7) / 8;
  }
  return 0;
}

void UnpackPixels(const PixelFormatInfo& format, const uint8_t* data, size_t size, int width,
                  int height, std::vector<uint16_t>* samples) {
  const size_t needed = PayloadBytes(format, width, height);
  if (size < needed) {
    throw DeviceError(std::string("pixel format ") + format.name + ": frame of " +
                      std::to_string(width) + "x" + std::to_string(height) + " needs " +
                      std::to_string(needed) + " bytes, got " + std::to_string(size) +
                      " (truncated frame; check the camera's packet size and the network)");
  }
  const size_t n_samples = static_cast<size_t>(width) * static_cast<size_t>(height) *
                           static_cast<size_t>(SamplesPerPixel(format.layout));
  samples->resize(n_samples);
  uint16_t* out = samples->data();
  switch (format.packing) {
    case PixelPacking::k8Bit:
      for (size_t i = 0; i < n_samples; ++i) out[i] = data[i];
      break;
    case PixelPacking::kBgr8:
      for (size_t p = 0; p < n_samples; p += 3) {
        out[p] = data[p + 2];
        out[p + 1] = data[p + 1];
        out[p + 2] = data[p];
      }
      break;
    case PixelPacking::k16BitLE: {
      const uint16_t mask = static_cast<uint16_t>((1u << format.bit_depth) - 1u);
      for (size_t i = 0; i < n_samples; ++i) {
        out[i] = static_cast<uint16_t>((data[2 * i] | (data[2 * i + 1] << 8)) & mask);
      }
      break;
    }
    case PixelPacking::kGvPacked12:
      for (size_t i = 0; i < n_samples; i += 2) {
        const uint8_t* b = data + (i / 2) * 3;
        out[i] = static_cast<uint16_t>((b[0] << 4) | (b[1] & 0x0f));
        if (i + 1 < n_samples) out[i + 1] = static_cast<uint16_t>((b[2] << 4) | (b[1] >> 4));
      }
      break;
    case PixelPacking::kPfnc12p:
      for (size_t i = 0; i < n_samples; i += 2) {
        const uint8_t* b = data + (i / 2) * 3;
        out[i] = static_cast<uint16_t>(b[0] | ((b[1] & 0x0f) << 8));
        if (i + 1 < n_samples) out[i + 1] = static_cast<uint16_t>((b[1] >> 4) | (b[2] << 4));
      }
      break;
  }
}

void PackPixels(const PixelFormatInfo& format, const std::vector<uint16_t>& samples, int width,
                int height, uint8_t* data) {
  const size_t n_samples = static_cast<size_t>(width) * static_cast<size_t>(height) *
                           static_cast<size_t>(SamplesPerPixel(format.layout));
  if (samples.size() != n_samples) {
    throw InputError(std::string("pixel format ") + format.name + ": expected " +
                     std::to_string(n_samples) + " samples for " + std::to_string(width) + "x" +
                     std::to_string(height) + ", got " + std::to_string(samples.size()));
  }
  const uint32_t max_value = (1u << format.bit_depth) - 1u;
  for (size_t i = 0; i < n_samples; ++i) {
    if (samples[i] > max_value) {
      throw InputError(std::string("pixel format ") + format.name + ": sample " +
                       std::to_string(i) + " is " + std::to_string(samples[i]) +
                       ", above the format's maximum " + std::to_string(max_value));
    }
  }
  const uint16_t* in = samples.data();
  switch (format.packing) {
    case PixelPacking::k8Bit:
      for (size_t i = 0; i < n_samples; ++i) data[i] = static_cast<uint8_t>(in[i]);
      break;
    case PixelPacking::kBgr8:
      for (size_t p = 0; p < n_samples; p += 3) {
        data[p] = static_cast<uint8_t>(in[p + 2]);
        data[p + 1] = static_cast<uint8_t>(in[p + 1]);
        data[p + 2] = static_cast<uint8_t>(in[p]);
      }
      break;
    case PixelPacking::k16BitLE:
      for (size_t i = 0; i < n_samples; ++i) {
        data[2 * i] = static_cast<uint8_t>(in[i] & 0xff);
        data[2 * i + 1] = static_cast<uint8_t>(in[i] >> 8);
      }
      break;
    case PixelPacking::kGvPacked12:
      for (size_t i = 0; i < n_samples; i += 2) {
        uint8_t* b = data + (i / 2) * 3;
        const uint16_t p0 = in[i];
        const uint16_t p1 = i + 1 < n_samples ? in[i + 1] : 0;
        b[0] = static_cast<uint8_t>(p0 >> 4);
        b[1] = static_cast<uint8_t>(((p1 & 0x0f) << 4) | (p0 & 0x0f));
        if (i + 1 < n_samples) b[2] = static_cast<uint8_t>(p1 >> 4);
      }
      break;
    case PixelPacking::kPfnc12p:
      for (size_t i = 0; i < n_samples; i += 2) {
        uint8_t* b = data + (i / 2) * 3;
        const uint16_t p0 = in[i];
        const uint16_t p1 = i + 1 < n_samples ? in[i + 1] : 0;
        b[0] = static_cast<uint8_t>(p0 & 0xff);
        b[1] = static_cast<uint8_t>(((p1 & 0x0f) << 4) | (p0 >> 8));
        if (i + 1 < n_samples) b[2] = static_cast<uint8_t>(p1 >> 4);
      }
      break;
  }
}

}  // namespace zbrdf
