// Forward imaging: raw camera frames of a material under projector patterns.
//
// Each camera pixel integrates f_r(w_i, w_r) cos(theta_i) L_i(w_i) over incident directions,
// over the pixel's area and over the lens aperture (which spreads w_r). L_i(w_i) is the
// radiance of the projector pixel that lights the sample center from w_i (pattern level through
// the projector response, flat field, beam splitter and mirror reflectances). The integral is
// estimated once per material. Its smooth part is taken exactly: per camera pixel the BRDF is
// fitted (least squares on probe directions, the brightest quarter left out) by a control
// variate c(w_i) = sum_k c_k b_k(w_i) in b = (1, z, z^2, x, y), whose integral against any
// pattern is sum_k c_k M_k with M_k from the projector pixels' footprint moments
// (RigMaps::projector_moments); a Lambertian is then integrated exactly, and a material whose
// f_r is constant (Brdf::ConstantValue) is that alone: its transport has no entries. The rest,
// f - c, comes from a fixed set of samples per pixel: cosine-weighted over the directions that
// reach the projector plus samples of the material's glossy lobe, combined by multiple
// importance sampling (Veach 1997), each from a scrambled (0,m,2)-net. Nothing depends on the
// pattern, so a frame is a linear function of it: the samples are stored as a
// sparse transport matrix (camera pixel x projector pixel) and a frame is one sparse product,
// followed by the sensor model (shot and read noise, black level, full well, quantization,
// clipping) on the Bayer mosaic.
//
// For a delta material (a flat mirror) each aperture ray is followed exactly from where it
// lands, through the mirrors to the projector lens, so gray-code correspondences are exact.
// Otherwise the incident light field is taken at the sample center, uniform over the small
// footprint a pixel sees.
#pragma once

#include <array>
#include <cstdint>
#include <future>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "basis/progress.h"
#include "brdf/brdf.h"
#include "drivers/camera.h"
#include "drivers/projector.h"
#include "rig/direction_maps.h"
#include "rig/optics.h"
#include "simulate/sensor_pixels.h"  // HashMix, UniformFromHash
#include "simulate/transport_row.h"

namespace zbrdf {

// $ZBRDF_TRANSPORT_CACHE_MB megabytes if set (0 turns the cache off), else 4 GB.
uint64_t DefaultTransportCacheBytes();

struct ForwardModelOptions {
  uint64_t seed = 1;  // selects the sample points (and, with noise_key, the sensor noise)
  // Integrate only camera rows y with y % row_stride == 0 (the others read 0): quick looks and
  // convergence studies at many samples.
  int row_stride = 1;
  ProgressCallback progress;
  // Folder of the transport cache (docs/simulator.md, "Transport cache"); empty: no cache. An
  // entry is keyed by the rig (RigHash), the material (MaterialCacheKey), seed and row_stride,
  // so every capture, order and session of the same rig and material shares one build. A
  // built transport is written there on a background thread (ForwardModel::WaitForCacheWrite).
  std::string cache_dir;
  // The cache folder is trimmed to this many bytes after a write, least recently used entries
  // first; an entry larger than this is not written. 0: the cache is neither read nor written.
  uint64_t cache_max_bytes = DefaultTransportCacheBytes();
  // Which of the transport's two sampling strategies keep their samples (a diagnostic of where
  // its Monte Carlo error comes from; docs/simulator.md, "Where the transport's error comes
  // from"). Samples are drawn and weighted as always (balance heuristic), and those of a
  // strategy left out are dropped, so the frames of kZoneOnly and kLobeOnly add up to those of
  // kBoth plus those of kControlOnly (the control variate's exact part, in each of them). Any
  // value other than kBoth builds the transport without the cache.
  enum class Strategies { kBoth, kZoneOnly, kLobeOnly, kControlOnly };
  Strategies strategies = Strategies::kBoth;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

class ForwardModel {
 public:
  // Builds the transport for `material` (kept by reference for the model's lifetime), or
  // loads it from the cache. A built one is written to the cache on a background thread, so
  // that frames need not wait for the disk (a full-resolution transport is ~0.8 GB).
  ForwardModel(const OpticalSystem& optics, const RigMaps& maps, const Brdf& material,
               const ForwardModelOptions& options = {});
  // Waits for the cache write, if one is running.
  ~ForwardModel();
  ForwardModel(const ForwardModel&) = delete;
  ForwardModel& operator=(const ForwardModel&) = delete;

  // Blocks until this model's transport is in the cache folder (or its write failed, which
  // only costs the next run a rebuild). A model of the same cache entry constructed meanwhile
  // in this process waits for it too, instead of building the transport again.
  void WaitForCacheWrite() const;

  // Radiance (W m^-2 sr^-1) reaching the sample from each projector pixel under the pattern.
  // Throws InputError if the pattern does not match the projector's size and bit depth.
  std::vector<float> ProjectorRadiance(const Pattern& pattern) const;
  // Mean photo-electrons per second at each camera pixel, noise-free and unclipped.
  std::vector<float> ElectronRate(const Pattern& pattern) const;
  // ElectronRate of each pattern, equal to it bit for bit, read off the transport in one pass
  // per kRowProductPatterns patterns: about the cost of two single products for eight (a
  // product mostly reads the transport). For a projector that is told what comes next
  // (Projector::Upcoming). Throws InputError naming the first pattern that does not fit.
  std::vector<std::vector<float>> ElectronRates(std::span<const Pattern> patterns) const;
  // The raw frame for an electron rate and exposure. noise_key selects the noise realization;
  // with add_noise false, only black level, full well, quantization and clipping apply.
  Frame RenderFromRate(const std::vector<float>& electron_rate, double exposure_us,
                       uint64_t noise_key, bool add_noise) const;
  Frame Render(const Pattern& pattern, double exposure_us, uint64_t noise_key,
               bool add_noise = true) const {
    return RenderFromRate(ElectronRate(pattern), exposure_us, noise_key, add_noise);
  }

  // Electrons per second per unit sample radiance (W m^-2 sr^-1) at a camera pixel: etendue,
  // beam splitter and mirror transmission, quantum efficiency. Excludes the pixel's throughput.
  double CameraConstant(int pixel) const { return camera_constant_[pixel]; }
  // Radiance reaching the sample per unit projector output (beam splitter, two mirrors).
  double ProjectorPathTransmission() const;

  // Stored entries of the transport: one per (camera pixel, projector pixel) pair that a sample
  // reached, plus a zero-weight step wherever two projector pixels of a camera pixel lie more
  // than 65535 apart (rare).
  size_t transport_entries() const { return packed_.size(); }

  // What the sampling did while the transport was built (all zero when it came from the
  // cache). Lobe samples are the draws from the material's glossy sampler; of them, those that
  // gave no direction, or one below the horizon or outside the lit zone, carry no light.
  struct SampleCounts {
    int64_t zone = 0;  // drawn over the lit zone, cosine-weighted
    int64_t lobe = 0;  // draws from the glossy sampler
    int64_t lobe_no_sample = 0;  // of them: no direction (a pdf of 0)
    int64_t lobe_below_horizon = 0;
    int64_t lobe_unlit = 0;  // above the horizon, outside the lit zone

    SampleCounts& operator+=(const SampleCounts& o) {
      zone += o.zone;
      lobe += o.lobe;
      lobe_no_sample += o.lobe_no_sample;
      lobe_below_horizon += o.lobe_below_horizon;
      lobe_unlit += o.lobe_unlit;
      return *this;
    }
    bool operator==(const SampleCounts&) const = default;
  };
  const SampleCounts& sample_counts() const { return sample_counts_; }

  double build_seconds() const { return build_seconds_; }
  // Whether the transport came from the cache (else it was built, and written there if allowed).
  bool from_cache() const { return from_cache_; }
  const OpticalSystem& optics() const { return optics_; }
  const RigMaps& maps() const { return maps_; }

 private:
  void BuildTransport(const Brdf& material);
  std::string CacheKey(const Brdf& material) const;
  // ElectronRate of a pattern's ProjectorRadiance.
  std::vector<float> RateOfRadiance(const std::vector<float>& radiance) const;
  // The pattern's footprint moments M_k = sum_j moments_jk L_j (radiance L), for the control
  // variates.
  std::array<double, kFootprintMoments> PatternMoments(const std::vector<float>& radiance) const;
  // Camera pixel p's packed entries (see packed_ below).
  std::span<const TransportEntry> Row(int64_t p) const {
    return {packed_.data() + row_begin_[p], static_cast<size_t>(row_begin_[p + 1] - row_begin_[p])};
  }
  // The rate at camera pixel p from the moments and the row's product with the radiance.
  float PixelRate(int64_t p, const std::array<double, kFootprintMoments>& moments,
                  double product) const {
    double sum = 0;
    for (int k = 0; k < kFootprintMoments; ++k) {
      sum += control_[p * kFootprintMoments + k] * moments[k];
    }
    // The entries' weights are in units of the pixel's scale (see packed_ below).
    return static_cast<float>(sum + weight_scale_[p] * product);
  }
  bool LoadCached(const std::string& path, const std::string& key);
  void SaveCached(const std::string& path, const std::string& key) const;

  const OpticalSystem& optics_;
  const RigMaps& maps_;
  ForwardModelOptions options_;
  std::vector<double> camera_constant_;
  // The transport in 4 bytes per entry (half the memory traffic of a frame's sparse product
  // and of the cache file, against an index and a float): camera pixel p's entries are
  // packed_[row_begin_[p], row_begin_[p + 1]), in ascending projector pixel; each steps that
  // pixel on from the previous one, the first from first_index_[p], and its weight, electrons/s
  // per unit projector-pixel radiance at the sample, is weight * weight_scale_[p], the scale
  // chosen so that the pixel's largest |weight| is 32767. The rounding (at most 1.5e-5 of the
  // pixel's largest entry) changes a frame by 7e-6 RMS relative for merl:blue-acrylic, under
  // 1/500 of its Monte Carlo error (docs/simulator.md, "Transport storage").
  std::vector<int64_t> row_begin_;     // camera pixel -> first entry (size pixels + 1)
  std::vector<uint32_t> first_index_;  // camera pixel -> projector pixel its steps start from
  std::vector<float> weight_scale_;    // camera pixel -> electrons/s per radiance per unit weight
  std::vector<TransportEntry> packed_;
  // Per camera pixel, kFootprintMoments control-variate coefficients times the pixel's constant.
  std::vector<float> control_;
  SampleCounts sample_counts_;
  double build_seconds_ = 0;
  bool from_cache_ = false;
  std::string cache_path_;                // the cache entry being written, if any
  std::shared_future<void> cache_write_;  // SaveCached on its own thread
};

}  // namespace zbrdf
