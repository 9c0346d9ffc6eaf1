#include "acquisition/hdr.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "basis/error.h"
#include "basis/parallel.h"
#include "drivers/demosaic.h"

namespace zbrdf {

HdrImage MergeExposures(const std::vector<Frame>& frames, const RigCalibration& c,
                        const std::string& what, const HdrOptions& options) {
  if (frames.empty()) throw InputError(what + ": no frames to merge");
  HdrImage hdr;
  hdr.width = frames[0].width;
  hdr.height = frames[0].height;
  hdr.layout = frames[0].layout;
  const size_t pixels = static_cast<size_t>(hdr.width) * hdr.height;
  for (const Frame& f : frames) {
    if (f.width != c.camera_width || f.height != c.camera_height || f.layout != hdr.layout ||
        f.data.size() != pixels || f.layout == PixelLayout::kRgb) {
      throw InputError(what + ": frame is " + std::to_string(f.width) + "x" +
                       std::to_string(f.height) + " " + PixelLayoutName(f.layout) +
                       " but the camera calibration is " + std::to_string(c.camera_width) + "x" +
                       std::to_string(c.camera_height) + "; frames of another camera or mode?");
    }
    if (!(f.exposure_us > 0 && std::isfinite(f.exposure_us))) {
      throw InputError(what + ": a frame has no valid exposure time");
    }
  }
  const double max_value = std::ldexp(1.0, frames[0].bit_depth) - 1;
  const double safe = c.black_dn + options.safe_saturation_fraction * (c.saturation_dn - c.black_dn);
  const double g = c.gain_e_per_dn, read2 = c.read_noise_e * c.read_noise_e + g * g / 12;
  hdr.rate.assign(pixels, 0.0f);
  hdr.variance.assign(pixels, 0.0f);
  hdr.valid.assign(pixels, 0);
  // Longest exposure first: the first usable sample seeds the estimate.
  std::vector<const Frame*> order;
  for (const Frame& f : frames) order.push_back(&f);
  std::sort(order.begin(), order.end(),
            [](const Frame* a, const Frame* b) { return a->exposure_us > b->exposure_us; });
  std::atomic<int> saturated{0};
  std::atomic<bool> out_of_range{false};
  ParallelFor(static_cast<int64_t>(pixels), 16384, [&](int64_t p0, int64_t p1) {
    int local_saturated = 0;
    std::vector<double> x(order.size()), t(order.size());
    for (int64_t p = p0; p < p1; ++p) {
      int n = 0;
      for (const Frame* f : order) {
        const double v = f->data[p];
        if (v > max_value) out_of_range = true;
        if (v >= safe) continue;
        t[n] = f->exposure_us * 1e-6;
        x[n] = (v - c.black_dn) * g / t[n];
        ++n;
      }
      if (n == 0) {
        ++local_saturated;
        continue;
      }
      double estimate = std::max(0.0, x[0]), weight_sum = 0;
      for (int it = 0; it < options.iterations; ++it) {
        double sum = 0;
        weight_sum = 0;
        for (int j = 0; j < n; ++j) {
          const double var = (std::max(0.0, estimate) * t[j] + read2) / (t[j] * t[j]);
          sum += x[j] / var;
          weight_sum += 1 / var;
        }
        estimate = sum / weight_sum;
      }
      hdr.rate[p] = static_cast<float>(estimate);
      hdr.variance[p] = static_cast<float>(1 / weight_sum);
      hdr.valid[p] = 1;
    }
    saturated += local_saturated;
  });
  if (out_of_range) {
    throw InputError(what + ": frame values exceed the declared " +
                     std::to_string(frames[0].bit_depth) + "-bit range; damaged frame?");
  }
  hdr.saturated_pixels = saturated.load();
  return hdr;
}

cv::Mat HdrToRgb(const HdrImage& hdr) {
  double max_rate = 0;
  for (size_t i = 0; i < hdr.rate.size(); ++i) max_rate = std::max<double>(max_rate, hdr.rate[i]);
  const double scale = max_rate > 0 ? 65535.0 / max_rate : 1.0;
  Frame mosaic;
  mosaic.width = hdr.width;
  mosaic.height = hdr.height;
  mosaic.layout = hdr.layout;
  mosaic.bit_depth = 16;
  mosaic.data.resize(hdr.rate.size());
  for (size_t i = 0; i < hdr.rate.size(); ++i) {
    mosaic.data[i] = static_cast<uint16_t>(std::clamp(std::lround(hdr.rate[i] * scale), 0L, 65535L));
  }
  cv::Mat rgb = DemosaicToRgb(mosaic);  // CV_32FC3, R G B, in 16-bit counts
  rgb *= 1.0 / scale;
  return rgb;
}

}  // namespace zbrdf
