#include "acquisition/hdr.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "drivers/demosaic.h"

namespace zbrdf {

void HdrOptions::Validate() const {
  OptionChecker check("HdrOptions");
  check.InRangeAbove("safe_saturation_fraction", safe_saturation_fraction, 0, 1)
      .InRange("iterations", iterations, 1, 100)
      .ThrowIfInvalid();
}

HdrImage MergeExposures(const std::vector<Frame>& frames, const RigCalibration& c,
                        const std::string& what, const HdrOptions& options) {
  options.Validate();
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
  const float max_value = static_cast<float>(std::ldexp(1.0, frames[0].bit_depth) - 1);
  const float safe = static_cast<float>(
      c.black_dn + options.safe_saturation_fraction * (c.saturation_dn - c.black_dn));
  const float black = static_cast<float>(c.black_dn);
  const double g = c.gain_e_per_dn;
  const float read2 = static_cast<float>(c.read_noise_e * c.read_noise_e + g * g / 12);
  hdr.rate.assign(pixels, 0.0f);
  hdr.variance.assign(pixels, 0.0f);
  hdr.valid.assign(pixels, 0);
  // Shortest exposure first, so that the last usable sample written into the seed is the
  // longest exposure's (the least noisy one).
  struct Exposure {
    const uint16_t* data;
    float t_s, t2_s2, e_per_dn_per_s;  // t, t^2, g / t
  };
  std::vector<Exposure> order;
  for (const Frame& f : frames) {
    const double t = f.exposure_us * 1e-6;
    order.push_back({f.data.data(), static_cast<float>(t), static_cast<float>(t * t),
                     static_cast<float>(g / t)});
  }
  std::sort(order.begin(), order.end(),
            [](const Exposure& a, const Exposure& b) { return a.t_s < b.t_s; });
  std::atomic<int> saturated{0};
  std::atomic<bool> out_of_range{false};
  // Blocks of pixels with branch-free inner loops over one exposure at a time (they vectorize);
  // float precision is ample for rates and weights (relative rounding 6e-8).
  constexpr int64_t kBlock = 2048;
  const int iterations = options.iterations;
  ParallelFor(static_cast<int64_t>(pixels), kBlock, [&, safe, black, read2](int64_t p0, int64_t p1) {
    float estimate[kBlock], sum[kBlock], weight_sum[kBlock], usable_count[kBlock];
    const int64_t n = p1 - p0;
    std::fill_n(estimate, n, 0.0f);
    std::fill_n(usable_count, n, 0.0f);
    unsigned block_max = 0;
    for (const Exposure& e : order) {
      const uint16_t* __restrict v = e.data + p0;
      const float scale = e.e_per_dn_per_s;
      for (int64_t i = 0; i < n; ++i) {
        const unsigned raw = v[i];
        block_max = std::max(block_max, raw);
        const float value = static_cast<float>(raw);
        const float usable = value < safe ? 1.0f : 0.0f;
        const float x = std::max(0.0f, (value - black) * scale);
        estimate[i] += usable * (x - estimate[i]);  // the longest usable exposure wins
        usable_count[i] += usable;
      }
    }
    if (block_max > max_value) out_of_range = true;
    for (int it = 0; it < iterations; ++it) {
      std::fill_n(sum, n, 0.0f);
      std::fill_n(weight_sum, n, 0.0f);
      for (const Exposure& e : order) {
        const uint16_t* __restrict v = e.data + p0;
        const float t = e.t_s, t2 = e.t2_s2, scale = e.e_per_dn_per_s;
        for (int64_t i = 0; i < n; ++i) {
          const float value = static_cast<float>(v[i]);
          // weight 1 / var = t^2 / (X t + read^2), var evaluated at the current estimate
          // (the denominator is >= read^2 > 0, so the division is always safe)
          const float usable = value < safe ? 1.0f : 0.0f;
          const float w = usable * (t2 / (estimate[i] * t + read2));
          sum[i] += w * ((value - black) * scale);
          weight_sum[i] += w;
        }
      }
      for (int64_t i = 0; i < n; ++i) {
        const float mean = sum[i] / std::max(weight_sum[i], 1e-30f);
        estimate[i] = std::max(0.0f, mean);
      }
    }
    int local_saturated = 0;
    for (int64_t i = 0; i < n; ++i) {
      const bool ok = usable_count[i] > 0;
      local_saturated += !ok;
      hdr.valid[p0 + i] = ok;
      if (!ok) continue;
      hdr.rate[p0 + i] = sum[i] / weight_sum[i];  // the weighted mean, negative if so
      hdr.variance[p0 + i] = 1.0f / weight_sum[i];
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

namespace {

// std::clamp(std::lround(x), 0, 65535) without the library call (a tenth of the HDR images'
// CPU, per pixel of every image): halves away from zero as lround, NaN and negatives to 0.
inline uint16_t RoundToUint16(double x) {
  if (!(x > 0)) return 0;
  if (x >= 65535) return 65535;
  const int whole = static_cast<int>(x);  // truncation; x - whole is exact
  return static_cast<uint16_t>(whole + (x - whole >= 0.5 ? 1 : 0));
}

}  // namespace

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
    mosaic.data[i] = RoundToUint16(hdr.rate[i] * scale);
  }
  cv::Mat rgb = DemosaicToRgb(mosaic);  // CV_32FC3, R G B, in 16-bit counts
  rgb *= 1.0 / scale;
  return rgb;
}

}  // namespace zbrdf
