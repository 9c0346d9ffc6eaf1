#include "drivers/camera.h"

#include <arpa/inet.h>

#include "basis/error.h"

namespace zbrdf {

namespace {
struct LayoutName {
  PixelLayout layout;
  const char* name;
};
constexpr LayoutName kLayoutNames[] = {
    {PixelLayout::kMono, "mono"},           {PixelLayout::kBayerRGGB, "bayer-rggb"},
    {PixelLayout::kBayerGRBG, "bayer-grbg"}, {PixelLayout::kBayerGBRG, "bayer-gbrg"},
    {PixelLayout::kBayerBGGR, "bayer-bggr"}, {PixelLayout::kRgb, "rgb"},
};
}  // namespace

std::string PixelLayoutName(PixelLayout layout) {
  for (const auto& entry : kLayoutNames) {
    if (entry.layout == layout) return entry.name;
  }
  return "unknown";
}

PixelLayout ParsePixelLayout(const std::string& name) {
  for (const auto& entry : kLayoutNames) {
    if (name == entry.name) return entry.layout;
  }
  throw InputError("unknown pixel layout '" + name +
                   "'; use one of mono, bayer-rggb, bayer-grbg, bayer-gbrg, bayer-bggr, rgb");
}

bool IsIpv4Address(const std::string& text) {
  in_addr address{};
  return inet_pton(AF_INET, text.c_str(), &address) == 1;
}

}  // namespace zbrdf
