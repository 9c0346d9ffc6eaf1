#include "calibration/gray_code.h"

#include <algorithm>
#include <cmath>

#include "basis/error.h"

namespace zbrdf {

Correspondences Correspondences::FromImage(const FloatImage& image, const std::string& what) {
  Correspondences c;
  c.camera_width = image.width;
  c.camera_height = image.height;
  if (!image.channels.count("u") || !image.channels.count("v")) {
    throw InputError(what + " has no u and v channels; re-run zbrdf calibrate geometry");
  }
  c.u = image.channels.at("u");
  c.v = image.channels.at("v");
  if (image.channels.count("contrast")) c.contrast = image.channels.at("contrast");
  for (size_t i = 0; i < c.u.size(); ++i) c.count += c.u[i] >= 0;
  return c;
}

FloatImage Correspondences::ToImage() const {
  FloatImage image;
  image.width = camera_width;
  image.height = camera_height;
  image.channels["u"] = u;
  image.channels["v"] = v;
  if (contrast.size() == u.size()) image.channels["contrast"] = contrast;
  return image;
}

int GrayCodeBits(int n) {
  int bits = 0;
  while ((1 << bits) < n) ++bits;
  return std::max(bits, 1);
}

Pattern GrayCodePattern(const RigCalibration& c, int bit, bool rows, bool inverted) {
  Pattern p = UniformPattern(c, 0);
  const uint16_t on = static_cast<uint16_t>((1 << c.projector_bit_depth) - 1);
  for (int y = 0; y < p.height; ++y) {
    for (int x = 0; x < p.width; ++x) {
      const unsigned index = static_cast<unsigned>(rows ? y : x);
      const bool set = (((index ^ (index >> 1)) >> bit) & 1u) != 0;
      p.levels[static_cast<size_t>(y) * p.width + x] = set != inverted ? on : 0;
    }
  }
  return p;
}

Correspondences CaptureGrayCode(CalibrationRig& rig, const RigCalibration& c) {
  const double exposure = MeterWhite(rig, c);
  const int bits_u = GrayCodeBits(c.projector_width), bits_v = GrayCodeBits(c.projector_height);
  const long total = 2 + 2 * (bits_u + bits_v);
  long done = 0;
  auto shoot = [&](const Pattern& p) {
    ShowPattern(rig, p);
    Frame f = TakeFrame(rig, exposure);
    Report(rig.progress, {"gray code", ++done, total, "frames"});
    return f;
  };
  const Frame white = shoot(UniformPattern(c, (1 << c.projector_bit_depth) - 1));
  const Frame black = shoot(UniformPattern(c, 0));
  const size_t pixels = white.data.size();
  // Contrast threshold: a quarter of the bright pixels' contrast, and well above the noise.
  std::vector<float> contrast(pixels);
  for (size_t i = 0; i < pixels; ++i) contrast[i] = static_cast<float>(white.data[i]) - black.data[i];
  std::vector<float> sorted = contrast;
  const size_t q = sorted.size() * 99 / 100;
  std::nth_element(sorted.begin(), sorted.begin() + q, sorted.end());
  const double noise_dn = c.read_noise_e / c.gain_e_per_dn;
  const float threshold = static_cast<float>(std::max(0.25 * sorted[q], 10 * noise_dn + 2));
  Correspondences out;
  out.camera_width = white.width;
  out.camera_height = white.height;
  std::vector<uint32_t> code_u(pixels, 0), code_v(pixels, 0);
  for (int pass = 0; pass < 2; ++pass) {
    const bool rows = pass == 1;
    const int bits = rows ? bits_v : bits_u;
    std::vector<uint32_t>& code = rows ? code_v : code_u;
    for (int bit = bits - 1; bit >= 0; --bit) {
      const Frame on = shoot(GrayCodePattern(c, bit, rows, false));
      const Frame off = shoot(GrayCodePattern(c, bit, rows, true));
      for (size_t i = 0; i < pixels; ++i) {
        if (on.data[i] > off.data[i]) code[i] |= 1u << bit;
      }
    }
  }
  out.contrast = contrast;
  out.u.assign(pixels, -1.0f);
  out.v.assign(pixels, -1.0f);
  auto decode = [](uint32_t gray) {
    uint32_t binary = gray;
    for (uint32_t shift = gray >> 1; shift; shift >>= 1) binary ^= shift;
    return binary;
  };
  for (size_t i = 0; i < pixels; ++i) {
    if (contrast[i] < threshold) continue;
    const uint32_t u = decode(code_u[i]), v = decode(code_v[i]);
    if (u >= static_cast<uint32_t>(c.projector_width) || v >= static_cast<uint32_t>(c.projector_height)) continue;
    out.u[i] = static_cast<float>(u + 0.5);
    out.v[i] = static_cast<float>(v + 0.5);
    ++out.count;
  }
  if (out.count < 100) {
    throw DeviceError("gray code: only " + std::to_string(out.count) +
                      " camera pixels decoded; is the mirror target in place and the projector on?");
  }
  return out;
}

}  // namespace zbrdf
