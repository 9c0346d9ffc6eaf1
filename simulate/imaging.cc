#include "simulate/imaging.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <span>
#include <string>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/hash.h"
#include "basis/huge_pages.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "basis/table_trig.h"
#include "basis/zone.h"
#include "brdf/fingerprint.h"
#include "brdf/sampling.h"

namespace zbrdf {

namespace {

// Per-pixel sample points. Each pair of dimensions (pixel jitter, lens aperture, direction of
// the uniform strategy, direction of the lobe strategy) is a 2-D Hammersley set with a random
// digital shift (a scrambled (0,m,2)-net in base 2 when the count is a power of two); sets are
// paired by random permutations (Owen's padding). Seeded per pixel: deterministic.
uint32_t ReverseBits(uint32_t v) {
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  v = ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
  v = ((v >> 8) & 0x00FF00FFu) | ((v & 0x00FF00FFu) << 8);
  return (v >> 16) | (v << 16);
}

struct PointSet2 {
  std::vector<double> u, v;
  std::vector<int> order;  // scratch of ScrambledHammersley, kept to save an allocation per set
};

// fmod(x, 1) for x in [0, 1]: the same value without the library call (x - 1 is exact there).
inline double WrapUnit(double x) { return x >= 1.0 ? x - 1.0 : x; }

// n points of a 2-D Hammersley set, digitally shifted by random masks, in random order.
void ScrambledHammersley(int n, uint64_t& state, PointSet2* out) {
  out->u.resize(n);
  out->v.resize(n);
  if (n <= 0) return;
  state = HashMix(state);
  const uint32_t mask_u = static_cast<uint32_t>(state), mask_v = static_cast<uint32_t>(state >> 32);
  state = HashMix(state);
  const double shift = UniformFromHash(state);
  const bool power_of_two = (n & (n - 1)) == 0;
  int bits = 0;
  while ((1 << bits) < n) ++bits;
  std::vector<int>& order = out->order;
  order.resize(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  for (int i = n - 1; i > 0; --i) {
    state = HashMix(state);
    // A uniform index in [0, i] by the high half of a 64 x 64-bit product (Lemire 2019, "Fast
    // random integer generation in an interval"; bias below 2^-50 here) rather than state %
    // (i + 1): a 64-bit division per point had been a third of this function's time.
    const auto pick = static_cast<int>(
        (static_cast<unsigned __int128>(state) * static_cast<uint64_t>(i + 1)) >> 64);
    std::swap(order[i], order[pick]);
  }
  for (int k = 0; k < n; ++k) {
    const int i = order[k];
    if (power_of_two) {
      const uint32_t first = bits == 0 ? 0u : static_cast<uint32_t>(i) << (32 - bits);
      out->u[k] = (first ^ mask_u) * 0x1.0p-32;
    } else {
      out->u[k] = WrapUnit((i + shift) / n);  // i + shift < n: at most 1 by rounding
    }
    out->v[k] = (ReverseBits(static_cast<uint32_t>(i)) ^ mask_v) * 0x1.0p-32;
  }
}

using Entry = TransportSample;

// Sorts a pixel's entries by projector pixel, equal pixels in their original (sample) order: a
// least-significant-digit radix sort in two passes of half the index's bits each (10 for the
// thesis projector's 480000 pixels), for projectors of up to 2^24 pixels (std::stable_sort
// beyond). std::sort of a pixel's ~1000 entries cost 3.4% of a fast transport build; two passes
// of a fixed 12 bits spent most of their time zeroing and summing 4096 buckets for a few hundred
// entries (3.6% of a full-resolution build), half-width digits a sixteenth of that.
void SortByProjectorPixel(std::vector<Entry>* entries, std::vector<Entry>* scratch,
                          uint32_t projector_pixels) {
  constexpr int kMaxBits = 12;
  if (projector_pixels > (1u << (2 * kMaxBits))) {
    std::stable_sort(entries->begin(), entries->end(),
                     [](const Entry& a, const Entry& b) { return a.index < b.index; });
    return;
  }
  int index_bits = 1;
  while (index_bits < 2 * kMaxBits && (1u << index_bits) < projector_pixels) ++index_bits;
  const int bits = (index_bits + 1) / 2;  // at most kMaxBits
  const uint32_t buckets = 1u << bits, digit_mask = buckets - 1;
  scratch->resize(entries->size());
  std::vector<Entry>* from = entries;
  std::vector<Entry>* to = scratch;
  for (int pass = 0; pass < 2; ++pass) {
    const int shift = pass * bits;
    std::array<uint32_t, 1u << kMaxBits> start;
    std::fill_n(start.begin(), buckets, 0u);
    for (const Entry& e : *from) ++start[(e.index >> shift) & digit_mask];
    uint32_t offset = 0;
    for (uint32_t b = 0; b < buckets; ++b) {
      const uint32_t count = start[b];
      start[b] = offset;
      offset += count;
    }
    for (const Entry& e : *from) (*to)[start[(e.index >> shift) & digit_mask]++] = e;
    std::swap(from, to);
  }
  // After an even number of passes the result is back in *entries.
}

// The directions that reach the projector, as one theta interval per azimuth column of the
// direction grid, with the interval ends found exactly (bisection on traced rays). Samples are
// cosine-weighted over the union (density cos(theta) / C).
class Coverage {
 public:
  Coverage(const ProjectorDirectionGrid& grid, const std::function<bool(const Vec3&)>& covered)
      : step_(grid.step_rad), columns_per_rad_(grid.NodesPerRad()), n_phi_(grid.n_phi) {
    // Per column, the lit theta interval [lo, hi] (0, 0 where none).
    std::vector<double> lo(n_phi_, 0.0), hi(n_phi_, 0.0);
    sin2_lo_.assign(n_phi_, 0.0);
    sin2_span_.assign(n_phi_, 0.0);
    sin2_hi_.assign(n_phi_, 0.0);
    std::vector<double> column_weights(n_phi_, 0.0);
    double total = 0;
    for (int j = 0; j < n_phi_; ++j) {
      const double phi = (j + 0.5) * step_;
      int first = -1, last = -1;
      for (int i = 0; i < grid.n_theta; ++i) {
        const size_t k = static_cast<size_t>(i) * n_phi_;
        const bool node = grid.Covered(k + j) || grid.Covered(k + (j + 1) % n_phi_);
        if (node) {
          if (first < 0) first = i;
          last = i;
        }
      }
      if (first >= 0) {
        auto at = [&](double theta) { return covered(SphericalDirection(theta, phi)); };
        // Bisect between an uncovered and a covered angle at each end.
        auto refine = [&](double outside, double inside) {
          if (at(outside)) return outside;
          if (!at(inside)) return inside;
          for (int it = 0; it < 40; ++it) {
            const double mid = 0.5 * (outside + inside);
            (at(mid) ? inside : outside) = mid;
          }
          return inside;
        };
        lo[j] = refine(std::max(0.0, (first - 1) * step_), first * step_);
        hi[j] = refine(std::min(M_PI / 2, (last + 1) * step_), last * step_);
        if (hi[j] < lo[j]) hi[j] = lo[j];
        theta_min_ = std::min(theta_min_, lo[j]);
        theta_max_ = std::max(theta_max_, hi[j]);
      }
      // Projected solid angle of the column: integral cos(theta) dw = (sin^2 hi - sin^2 lo) / 2.
      sin2_lo_[j] = Sin2(lo[j]);
      sin2_hi_[j] = Sin2(hi[j]);
      sin2_span_[j] = sin2_hi_[j] - sin2_lo_[j];
      column_weights[j] = 0.5 * sin2_span_[j] * step_;
      total += column_weights[j];
    }
    if (!(total > 0)) throw NumericalError("no direction of the hemisphere reaches the projector");
    inverse_projected_solid_angle_ = 1.0 / total;
    columns_.emplace(column_weights);
  }

  // A direction with density Pdf, from u0, u1 in [0, 1); *phi_out (optional) is its azimuth in
  // [0, 2 pi], as sampled (SphericalPhi of the direction up to rounding).
  Vec3 Sample(double u0, double u1, double* phi_out = nullptr) const {
    // The column in proportion to its projected solid angle (never an empty one), and u0
    // rescaled within it for the azimuth.
    double t = 0;
    const int j = columns_->SampleDiscrete(u0, nullptr, &t);
    const double phi = (j + t) * step_;
    if (phi_out != nullptr) *phi_out = phi;
    // sin^2(theta) is uniform for a cosine-weighted density.
    const double sin2 = sin2_lo_[j] + u1 * sin2_span_[j];
    const double sin_theta = std::sqrt(sin2), cos_theta = std::sqrt(std::max(0.0, 1 - sin2));
    double sin_phi, cos_phi;
    TurnSinCos((j + t) / n_phi_, &sin_phi, &cos_phi);  // phi in turns
    return {sin_theta * cos_phi, sin_theta * sin_phi, cos_theta};
  }

  double Pdf(const Vec3& w) const {
    if (w.z <= 0) return 0;
    return PdfAzimuth(w, SphericalPhi(w));
  }
  // The same given w's SphericalPhi. The polar angle's test is on sin^2 theta = x^2 + y^2
  // (increasing in theta above the horizon): no acos per sample.
  double PdfAzimuth(const Vec3& w, double phi) const {
    if (w.z <= 0) return 0;
    const int j = std::min(static_cast<int>(phi * columns_per_rad_), n_phi_ - 1);
    const double sin2 = w.x * w.x + w.y * w.y;
    return sin2 >= sin2_lo_[j] && sin2 <= sin2_hi_[j] ? w.z * inverse_projected_solid_angle_ : 0.0;
  }

  double theta_min() const { return theta_min_; }
  double theta_max() const { return theta_max_; }

 private:
  static double Sin2(double theta) { return std::sin(theta) * std::sin(theta); }
  double step_, columns_per_rad_;
  int n_phi_;
  // Per column sin^2(lo), sin^2(hi) and their difference, once, instead of sines per sample.
  std::vector<double> sin2_lo_, sin2_hi_, sin2_span_;
  std::optional<Distribution1D> columns_;  // weights: the columns' projected solid angles
  double inverse_projected_solid_angle_ = 0;
  double theta_min_ = M_PI, theta_max_ = 0;
};

// Transport cache entries being written by this process (path -> the write): a model of the
// same entry waits for it rather than building the transport a second time.
std::mutex& PendingTransportWritesMutex() {
  static std::mutex mutex;
  return mutex;
}
std::map<std::string, std::shared_future<void>>& PendingTransportWrites() {
  static std::map<std::string, std::shared_future<void>> writes;
  return writes;
}

}  // namespace

void ForwardModelOptions::Validate() const {
  OptionChecker("ForwardModelOptions").AtLeast("row_stride", row_stride, 1).ThrowIfInvalid();
}

ForwardModel::ForwardModel(const OpticalSystem& optics, const RigMaps& maps, const Brdf& material,
                           const ForwardModelOptions& options)
    : optics_(optics), maps_(maps), options_(options) {
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  const Rig& rig = optics.rig();
  const ThinLens& camera = optics.camera();
  const int width = rig.camera.width, height = rig.camera.height;
  camera_constant_.resize(static_cast<size_t>(width) * height);
  const double transmission =
      rig.beam_splitter_transmission * rig.mirror_reflectance * rig.mirror_reflectance;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      camera_constant_[y * width + x] = camera.PixelEtendue(x + 0.5, y + 0.5) * transmission *
                                        rig.sensor.quantum_efficiency * kPhotonsPerJoule550nm;
    }
  }
  const bool use_cache = !options_.cache_dir.empty() && options_.cache_max_bytes > 0 &&
                         options_.strategies == ForwardModelOptions::Strategies::kBoth;
  std::string key, path;
  if (use_cache) {
    key = CacheKey(material);
    char name[48];
    std::snprintf(name, sizeof(name), "transport-%016llx.bin",
                  static_cast<unsigned long long>(Fnv1a64(key)));
    path = (std::filesystem::path(options_.cache_dir) / name).string();
    from_cache_ = LoadCached(path, key);
  }
  if (!from_cache_) {
    BuildTransport(material);
    if (use_cache) {
      // The transport is not changed after this: the write reads it while frames are rendered.
      cache_path_ = path;
      cache_write_ =
          std::async(std::launch::async, [this, path, key] { SaveCached(path, key); }).share();
      std::lock_guard<std::mutex> lock(PendingTransportWritesMutex());
      PendingTransportWrites()[path] = cache_write_;
    }
  }
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

ForwardModel::~ForwardModel() {
  WaitForCacheWrite();
  if (cache_write_.valid()) {
    std::lock_guard<std::mutex> lock(PendingTransportWritesMutex());
    const auto it = PendingTransportWrites().find(cache_path_);
    // Another model may have registered a newer write of the same entry since.
    if (it != PendingTransportWrites().end() &&
        it->second.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
      PendingTransportWrites().erase(it);
    }
  }
}

void ForwardModel::WaitForCacheWrite() const {
  if (cache_write_.valid()) cache_write_.wait();
}

uint64_t DefaultTransportCacheBytes() {
  if (const char* mb = std::getenv("ZBRDF_TRANSPORT_CACHE_MB"); mb && *mb) {
    char* end = nullptr;
    const double value = std::strtod(mb, &end);
    if (end != mb && *end == '\0' && value >= 0) return static_cast<uint64_t>(value * 1e6);
  }
  return 4'000'000'000ull;
}

namespace {

constexpr char kTransportMagic[8] = {'Z', 'B', 'R', 'D', 'F', 'T', 'R', 'N'};
constexpr char kTransportEnd[8] = {'Z', 'B', 'R', 'D', 'F', 'E', 'N', 'D'};
// Bump when BuildTransport's output changes for the same inputs.
// 7: the control variate's probes no longer depend on the seed; the half-vector proxy's lobe is
// the nearer probe's (brdf/proxy_sampler.h).
// 8: the network evaluated with fused multiply-adds where the CPU has them (brdf/nbrdf.cc); the
// direction grid in 16-bit fixed point (rig/direction_maps.h).
constexpr uint32_t kTransportVersion = 8;

// Removes the least recently used transport entries until the folder holds at most max_bytes.
void TrimTransportCache(const std::filesystem::path& folder, uint64_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code error;
  std::vector<std::pair<fs::file_time_type, fs::path>> entries;
  uint64_t total = 0;
  for (const auto& entry : fs::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("transport-", 0) != 0 || entry.path().extension() != ".bin") continue;
    const uint64_t size = entry.file_size(error);
    if (error) continue;
    total += size;
    entries.emplace_back(entry.last_write_time(error), entry.path());
  }
  std::sort(entries.begin(), entries.end());
  for (const auto& [time, entry_path] : entries) {
    if (total <= max_bytes) break;
    const uint64_t size = fs::file_size(entry_path, error);
    if (!error && fs::remove(entry_path, error)) total -= size;
  }
}

}  // namespace

std::string ForwardModel::CacheKey(const Brdf& material) const {
  char text[160];
  std::snprintf(text, sizeof(text),
                "zbrdf transport v%u rig %016llx seed %llu row_stride %d material ",
                kTransportVersion, static_cast<unsigned long long>(RigHash(optics_.rig())),
                static_cast<unsigned long long>(options_.seed), options_.row_stride);
  return text + MaterialCacheKey(material);
}

// Layout: magic, version, key length, key, pixels, entries, row_begin (pixels + 1 int64),
// first_index (pixels uint32), weight_scale (pixels float), entries (entries x {uint16 step,
// int16 weight}), control (pixels x kFootprintMoments float), end magic.
bool ForwardModel::LoadCached(const std::string& path, const std::string& key) {
  std::shared_future<void> pending;
  {
    std::lock_guard<std::mutex> lock(PendingTransportWritesMutex());
    const auto it = PendingTransportWrites().find(path);
    if (it != PendingTransportWrites().end()) pending = it->second;
  }
  if (pending.valid()) pending.wait();
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  char magic[8];
  uint32_t version = 0, key_size = 0;
  if (!in.read(magic, 8) || std::memcmp(magic, kTransportMagic, 8) != 0 ||
      !in.read(reinterpret_cast<char*>(&version), 4) || version != kTransportVersion ||
      !in.read(reinterpret_cast<char*>(&key_size), 4) || key_size != key.size()) {
    return false;
  }
  std::string stored(key_size, '\0');
  uint64_t pixels = 0, entries = 0;
  const uint64_t camera_pixels = camera_constant_.size();
  if (!in.read(stored.data(), key_size) || stored != key ||
      !in.read(reinterpret_cast<char*>(&pixels), 8) || pixels != camera_pixels ||
      !in.read(reinterpret_cast<char*>(&entries), 8) || entries > (1ull << 34)) {
    return false;
  }
  std::vector<int64_t> row_begin(pixels + 1);
  std::vector<uint32_t> first_index(pixels);
  std::vector<float> weight_scale(pixels), control(pixels * kFootprintMoments);
  std::vector<TransportEntry> packed;
  ResizeInHugePages(&packed, entries);  // unset until read (TransportEntry), in huge pages
  auto read = [&](auto& v) {
    return static_cast<bool>(in.read(reinterpret_cast<char*>(v.data()), v.size() * sizeof(v[0])));
  };
  if (!read(row_begin) || !read(first_index) || !read(weight_scale) || !read(packed) ||
      !read(control) || !in.read(magic, 8) || std::memcmp(magic, kTransportEnd, 8) != 0 ||
      in.peek() != std::char_traits<char>::eof()) {
    return false;
  }
  // A damaged entry must not index out of range: rows ascend within [0, entries], and every
  // pixel's steps stay below the projector's pixel count (summed in 64 bits: no wrap-around).
  if (row_begin[0] != 0 || row_begin[pixels] != static_cast<int64_t>(entries)) return false;
  const uint64_t projector_pixels = static_cast<uint64_t>(optics_.rig().projector.lens.width) *
                                    static_cast<uint64_t>(optics_.rig().projector.lens.height);
  for (uint64_t p = 0; p < pixels; ++p) {
    if (row_begin[p + 1] < row_begin[p] || first_index[p] >= projector_pixels ||
        !std::isfinite(weight_scale[p])) {
      return false;
    }
    uint64_t j = first_index[p];
    for (int64_t e = row_begin[p]; e < row_begin[p + 1]; ++e) j += packed[e].step;
    if (j >= projector_pixels) return false;
  }
  row_begin_ = std::move(row_begin);
  first_index_ = std::move(first_index);
  weight_scale_ = std::move(weight_scale);
  packed_ = std::move(packed);
  control_ = std::move(control);
  // The entry was used: it is the most recently used one when the folder is trimmed.
  std::error_code error;
  std::filesystem::last_write_time(path, std::filesystem::file_time_type::clock::now(), error);
  return true;
}

void ForwardModel::SaveCached(const std::string& path, const std::string& key) const {
  const uint32_t version = kTransportVersion, key_size = static_cast<uint32_t>(key.size());
  const uint64_t pixels = row_begin_.size() - 1, entries = packed_.size();
  const uint64_t bytes = 8 + 4 + 4 + key.size() + 16 + row_begin_.size() * 8 + pixels * 8 +
                         entries * sizeof(TransportEntry) + control_.size() * 4 + 8;
  if (bytes > options_.cache_max_bytes) return;
  const bool written = WriteCacheFile(
      path, {std::string_view(kTransportMagic, 8), ObjectBytes(&version), ObjectBytes(&key_size),
             key, ObjectBytes(&pixels), ObjectBytes(&entries), ObjectBytes(row_begin_),
             ObjectBytes(first_index_), ObjectBytes(weight_scale_), ObjectBytes(packed_),
             ObjectBytes(control_), std::string_view(kTransportEnd, 8)});
  if (written)
    TrimTransportCache(std::filesystem::path(path).parent_path(), options_.cache_max_bytes);
}

double ForwardModel::ProjectorPathTransmission() const {
  const Rig& rig = optics_.rig();
  return rig.beam_splitter_reflection * rig.mirror_reflectance * rig.mirror_reflectance;
}

void ForwardModel::BuildTransport(const Brdf& material) {
  const Rig& rig = optics_.rig();
  const ThinLens& camera = optics_.camera();
  const ThinLens& projector = optics_.projector();
  const int width = rig.camera.width, height = rig.camera.height;
  const int proj_w = rig.projector.lens.width, proj_h = rig.projector.lens.height;
  const int n = rig.simulation.samples_per_pixel;
  const int n_aperture = std::min(n, rig.simulation.aperture_samples);
  const bool delta = material.IsDelta();
  // An ideal diffuse material is integrated exactly by the control variate alone (below).
  const std::optional<Rgb> constant = material.ConstantValue();

  // Which projector pixel lights the sample point from w_i (-1: none). The direction grid is
  // exact enough inside the lit zone; near its edge, and for a delta material's exact paths,
  // the ray is traced.
  auto projector_pixel = [&](const Vec3& point, const Vec3& w_i, bool exact) -> int64_t {
    double px, py;
    if (exact || !maps_.grid.Lookup(w_i, &px, &py)) {
      const auto path = optics_.TraceFromSample(point, w_i);
      if (!path.reached) return -1;
      const auto proj = projector.Project(path.at_lens);
      if (!proj.in_front || !proj.in_aperture) return -1;
      px = proj.px;
      py = proj.py;
    }
    if (px < 0 || py < 0 || px >= proj_w || py >= proj_h) return -1;
    return static_cast<int64_t>(py) * proj_w + static_cast<int64_t>(px);
  };
  // projector_pixel({0, 0, 0}, w_i, false) for w_i above the horizon with known angles.
  auto projector_pixel_at_center = [&](const Vec3& w_i,
                                       std::pair<double, double> angles) -> int64_t {
    double px, py;
    if (!maps_.grid.LookupAngles(angles.first, angles.second, &px, &py)) {
      return projector_pixel({0, 0, 0}, w_i, true);
    }
    if (px < 0 || py < 0 || px >= proj_w || py >= proj_h) return -1;
    return static_cast<int64_t>(py) * proj_w + static_cast<int64_t>(px);
  };
  // Two strategies (Veach 1997), combined by the balance heuristic: cosine-weighted over the
  // lit directions, which integrates diffuse parts almost exactly and never wastes a sample
  // outside the zone; and the glossy part of the material's sampler (Brdf::SampleGlossy), for
  // peaks. The split follows the material's glossy probability at the pixel, within
  // [1/4, 3/4]; a material without a glossy part gets only the first.
  const Coverage coverage(maps_.grid, [&](const Vec3& w) {
    return projector_pixel({0, 0, 0}, w, true) >= 0;
  });
  // Probe directions for the control variate: cosine-weighted over the lit directions.
  constexpr int kProbes = 64;
  std::vector<Vec3> probes;
  {
    // The same probes for every seed (those seed 1 has always had): the coefficients need not
    // vary with the samples' seed, and with one control the strategies' parts of two seeds
    // estimate the same integrals (bench_simulate's BM_TransportConvergence compares them).
    uint64_t state = HashMix(1 ^ 0x9b0be5ull);
    PointSet2 points;
    ScrambledHammersley(kProbes, state, &points);
    for (int i = 0; i < kProbes; ++i) probes.push_back(coverage.Sample(points.u[i], points.v[i]));
  }
  std::vector<std::array<double, kFootprintMoments>> probe_basis(kProbes);
  for (int i = 0; i < kProbes; ++i) FootprintBasis(probes[i], probe_basis[i].data());
  const size_t camera_pixels = static_cast<size_t>(width) * height;
  control_.assign(camera_pixels * kFootprintMoments, 0.0f);

  static_assert(sizeof(TransportEntry) == 4,
                "the cache file's layout and the products' bandwidth assume 4 bytes");
  const size_t pixels = static_cast<size_t>(width) * height;
  // Each camera row is packed straight into the whole transport, at room for the most its lit
  // pixels can hold (PackedRowMaxEntries: a pixel has at most n samples' entries), then the rows
  // are moved down into place. The room is in huge pages and untouched until written: a row's
  // own vector, copied into the transport after, had touched every entry's memory twice, the
  // first time 4 kB page by page (the kernel's page faults were ~6% of the build).
  const uint32_t projector_pixels = static_cast<uint32_t>(proj_w) * static_cast<uint32_t>(proj_h);
  const size_t pixel_room = PackedRowMaxEntries(static_cast<size_t>(n), projector_pixels);
  std::vector<size_t> row_room_begin(height + 1, 0), row_used(height, 0);
  for (int y = 0; y < height; ++y) {
    size_t lit = 0;
    if (y % options_.row_stride == 0) {
      for (int x = 0; x < width; ++x) lit += maps_.camera.Valid(y * width + x);
    }
    row_room_begin[y + 1] = row_room_begin[y] + lit * pixel_room;
  }
  ResizeInHugePages(&packed_, row_room_begin[height]);
  first_index_.assign(pixels, 0);
  weight_scale_.assign(pixels, 0.0f);
  std::vector<int64_t> count(pixels, 0);  // entries per camera pixel (each written by one thread)
  std::atomic<long> rows_done{0};
  using Strategies = ForwardModelOptions::Strategies;
  const bool keep_zone =
      options_.strategies == Strategies::kBoth || options_.strategies == Strategies::kZoneOnly;
  const bool keep_lobe =
      options_.strategies == Strategies::kBoth || options_.strategies == Strategies::kLobeOnly;
  std::mutex counts_mutex;
  sample_counts_ = {};
  ParallelFor(height, 2, [&](int64_t y0, int64_t y1) {
    SampleCounts counts;
    std::vector<Entry> entries, sort_scratch;
    PointSet2 jitter, aperture, zone_dirs, lobe_dirs;
    std::vector<OpticalSystem::SamplePath> paths(n_aperture);
    std::vector<Brdf::GlossyView> views(n_aperture);  // the glossy part per path's w_o
    std::vector<Vec3> w_in(std::max(n, kProbes)), w_out(std::max(n, kProbes));
    std::vector<double> f_channel(std::max(n, kProbes));
    std::vector<double> weight(n);
    std::vector<std::pair<double, double>> angles(n);
    std::vector<std::pair<double, int>> probe_values(kProbes);
    std::vector<std::pair<Vec3, int64_t>> traced;  // a delta material's last trace per path
    for (int64_t y = y0; y < y1; ++y) {
      TransportEntry* const row = packed_.data() + row_room_begin[y];
      size_t& used = row_used[y];
      for (int x = 0; x < width; ++x) {
        const int pixel = static_cast<int>(y) * width + x;
        if (!maps_.camera.Valid(pixel) || y % options_.row_stride != 0) continue;
        const int channel = BayerChannel(rig.sensor.layout, x, static_cast<int>(y));
        uint64_t state =
            HashMix(options_.seed ^ HashMix(static_cast<uint64_t>(pixel) + 0x51ed2701ull));
        const double glossy =
            delta ? 1.0 : material.GlossyProbability(maps_.camera.Direction(pixel));
        const int n_lobe = delta ? n
                           : glossy > 0
                               ? static_cast<int>(std::lround(n * std::clamp(glossy, 0.25, 0.75)))
                               : 0;
        const int n_zone = n - n_lobe;
        ScrambledHammersley(n_aperture, state, &jitter);
        ScrambledHammersley(n_aperture, state, &aperture);
        ScrambledHammersley(n_zone, state, &zone_dirs);
        ScrambledHammersley(n_lobe, state, &lobe_dirs);
        state = HashMix(state);
        const double lobe_shift = UniformFromHash(state);
        // Rays over the pixel area and lens aperture. The pixel's throughput (the fraction of
        // such rays that land on the sample) comes from the camera map, traced with many rays
        // at the rim; directions go to the landed rays only, and are scaled by it.
        int landed = 0;
        for (int attempt = 0; attempt < 4 && landed == 0; ++attempt) {
          if (attempt > 0) {
            ScrambledHammersley(n_aperture, state, &jitter);
            ScrambledHammersley(n_aperture, state, &aperture);
          }
          for (int a = 0; a < n_aperture; ++a) {
            const auto path = optics_.TraceToSample(
                camera.GenerateRay(x + jitter.u[a], y + jitter.v[a], aperture.u[a], aperture.v[a]));
            if (path.status == OpticalSystem::PathStatus::kLanded) paths[landed++] = path;
          }
        }
        if (landed == 0) continue;
        const double k_pixel = camera_constant_[pixel] * maps_.camera.throughput[pixel];
        entries.clear();
        bool constant_here = constant.has_value();
        for (int a = 0; a < landed && constant_here; ++a) constant_here = paths[a].w.z > 0;
        if (delta) {
          // A path's samples usually reflect along one direction (a mirror's does whatever the
          // random numbers): its exact trace is reused while the sampled direction repeats.
          traced.assign(landed, {Vec3{0, 0, -1}, -1});
          counts.lobe += n;
          for (int s = 0; s < n; ++s) {
            const auto& path = paths[s % landed];
            const BrdfSample bs = material.Sample(path.w, 0.5, lobe_dirs.u[s], lobe_dirs.v[s]);
            if (bs.pdf <= 0 || !bs.is_delta) {
              ++counts.lobe_no_sample;
              continue;
            }
            if (bs.w_i.z <= 0) {
              ++counts.lobe_below_horizon;
              continue;
            }
            auto& [traced_w_i, index] = traced[s % landed];
            if (!(traced_w_i == bs.w_i)) {
              traced_w_i = bs.w_i;
              index = projector_pixel(path.landing_point, bs.w_i, true);
            }
            if (index < 0) {
              ++counts.lobe_unlit;
              continue;
            }
            if (!keep_lobe) continue;  // a diagnostic's split
            const double r =
                channel < 0 ? bs.delta_reflectance.Luminance() : bs.delta_reflectance[channel];
            entries.push_back({static_cast<uint32_t>(index), static_cast<float>(k_pixel * r / n)});
          }
        } else if (constant_here) {
          // f is the same for every w_i (and this pixel's w_o, all above the horizon): the
          // control variate c = f b_0 is f itself, f - c vanishes at every sample, and the
          // pixel's value is f times the projector's footprint moment M_0 under any pattern.
          const double v = channel < 0 ? constant->Luminance() : (*constant)[channel];
          control_[pixel * kFootprintMoments] = static_cast<float>(k_pixel * v);
        } else {
          // Control variate: least squares of f (the pixel's channel) at the probes, without
          // the brightest quarter (a glossy peak is the lobe samples' job).
          double coeff[kFootprintMoments] = {0, 0, 0, 0, 0};
          {
            const Vec3 w_r = maps_.camera.Direction(pixel);
            for (int i = 0; i < kProbes; ++i) {
              w_in[i] = probes[i];
              w_out[i] = w_r;
            }
            // Single precision, as the samples below: any coefficients give an unbiased
            // estimate (the control's integral is exact), these only have to be close.
            material.EvalChannelBatchSinglePrecision(std::span<const Vec3>(w_in.data(), kProbes),
                                                     std::span<const Vec3>(w_out.data(), kProbes),
                                                     channel,
                                                     std::span<double>(f_channel.data(), kProbes));
            for (int i = 0; i < kProbes; ++i) {
              const double v = f_channel[i];
              probe_values[i] = {std::isfinite(v) ? v : 0.0, i};
            }
            // The dimmest three quarters (ordered by value, then probe: the same set as a whole
            // sort's first 48), summed in the order nth_element leaves them.
            std::nth_element(probe_values.begin(), probe_values.begin() + kProbes * 3 / 4,
                             probe_values.end());
            Eigen::Matrix<double, kFootprintMoments, kFootprintMoments> normal =
                Eigen::Matrix<double, kFootprintMoments, kFootprintMoments>::Zero();
            Eigen::Matrix<double, kFootprintMoments, 1> rhs =
                Eigen::Matrix<double, kFootprintMoments, 1>::Zero();
            for (int i = 0; i < kProbes * 3 / 4; ++i) {
              const auto& b = probe_basis[probe_values[i].second];
              const Eigen::Map<const Eigen::Matrix<double, kFootprintMoments, 1>> bv(b.data());
              normal += bv * bv.transpose();
              rhs += probe_values[i].first * bv;
            }
            normal.diagonal().array() += 1e-9 * (normal.trace() + 1e-30);
            const Eigen::Matrix<double, kFootprintMoments, 1> c = normal.ldlt().solve(rhs);
            for (int k = 0; k < kFootprintMoments; ++k) {
              coeff[k] = std::isfinite(c(k)) ? c(k) : 0.0;
              control_[pixel * kFootprintMoments + k] = static_cast<float>(k_pixel * coeff[k]);
            }
          }
          // What the glossy sampler needs of each path's viewing direction, once per path
          // rather than per sample (n / landed samples share a path).
          if (n_lobe > 0) {
            for (int a = 0; a < landed; ++a) views[a] = material.PrepareGlossy(paths[a].w);
          }
          counts.zone += n_zone;  // one draw each, from the zone sampler then the glossy one
          counts.lobe += n_lobe;
          int m = 0;  // samples kept for evaluation
          for (int s = 0; s < n; ++s) {
            const auto& path = paths[s % landed];
            const Brdf::GlossyView& view = views[s % landed];
            const bool uniform = s < n_zone;
            Vec3 w_i;
            double p_lobe = -1;  // the glossy density at w_i, when the sampler already gave it
            double phi_i = -1;   // the zone sampler's azimuth of w_i, else computed below
            if (uniform) {
              w_i = coverage.Sample(zone_dirs.u[s], zone_dirs.v[s], &phi_i);
            } else {
              const int j = s - n_zone;
              const double u_lobe = WrapUnit((j + lobe_shift) / n_lobe);
              const BrdfSample bs =
                  material.SampleGlossyAt(view, u_lobe, lobe_dirs.u[j], lobe_dirs.v[j]);
              if (bs.pdf <= 0 || bs.is_delta) {
                ++counts.lobe_no_sample;
                continue;
              }
              w_i = bs.w_i;
              p_lobe =
                  bs.pdf;  // SampleGlossyAt's pdf is GlossyPdfAt(view, w_i): not computed twice
            }
            if (w_i.z <= 0) {
              counts.lobe_below_horizon += !uniform;
              continue;
            }
            if (phi_i < 0) phi_i = TableSphericalPhi(w_i);
            const double p_zone = coverage.PdfAzimuth(w_i, phi_i);
            if (p_zone <= 0) {  // not lit
              counts.lobe_unlit += !uniform;
              continue;
            }
            if (n_lobe > 0 && p_lobe < 0) p_lobe = material.GlossyPdfAt(view, w_i);
            const double q = n_zone * p_zone + (n_lobe > 0 ? n_lobe * p_lobe : 0.0);
            weight[m] = 1.0 / q;  // balance heuristic: f cos / (n_zone p_zone + n_lobe p_lobe)
            if (!(weight[m] > 0) || !std::isfinite(weight[m])) continue;
            if (!(uniform ? keep_zone : keep_lobe)) continue;  // a diagnostic's split
            w_in[m] = w_i;
            w_out[m] = path.w;
            // The polar angle only places the grid lookup in its cell (ApproxAcos's 1.3e-11
            // rad is 1e-8 of a cell).
            angles[m] = {ApproxAcos(w_i.z), phi_i};
            ++m;
          }
          // Single precision inside where the material has it: ~1e-6 against this sum's ~5e-3;
          // only the pixel's channel.
          material.EvalChannelBatchSinglePrecision(std::span<const Vec3>(w_in.data(), m),
                                                   std::span<const Vec3>(w_out.data(), m), channel,
                                                   std::span<double>(f_channel.data(), m));
          // The grid's nodes of sample i + kGridPrefetchAhead are fetched while sample i is
          // finished: the grid (26 MB at full resolution) is read at random, and a lookup that
          // waits for memory cost more than the rest of its sample's work here.
          constexpr int kGridPrefetchAhead = 16;
          for (int i = 0; i < std::min(m, kGridPrefetchAhead); ++i) {
            maps_.grid.PrefetchAngles(angles[i].first, angles[i].second);
          }
          for (int i = 0; i < m; ++i) {
            if (i + kGridPrefetchAhead < m) {
              const auto& ahead = angles[i + kGridPrefetchAhead];
              maps_.grid.PrefetchAngles(ahead.first, ahead.second);
            }
            double b[kFootprintMoments];
            FootprintBasis(w_in[i], b);
            double control = 0;
            for (int k = 0; k < kFootprintMoments; ++k) control += coeff[k] * b[k];
            const double value = (f_channel[i] - control) * w_in[i].z * weight[i];
            if (value == 0 || !std::isfinite(value)) continue;
            const int64_t index = projector_pixel_at_center(w_in[i], angles[i]);
            if (index < 0) continue;
            entries.push_back({static_cast<uint32_t>(index), static_cast<float>(k_pixel * value)});
          }
        }
        // Merge repeated projector pixels, in sample order.
        SortByProjectorPixel(&entries, &sort_scratch, static_cast<uint32_t>(proj_w * proj_h));
        size_t merged = 0;
        for (const Entry& e : entries) {
          if (merged > 0 && entries[merged - 1].index == e.index) {
            entries[merged - 1].weight += e.weight;
          } else {
            entries[merged++] = e;
          }
        }
        entries.resize(merged);
        // Pack (imaging.h): steps between projector pixels, weights in 1/32767 of the pixel's
        // largest |weight|.
        size_t packed = 0;
        const PackedRowStart start = PackRow(entries, row + used, &packed);
        ZBRDF_ASSERT(used + packed <= row_room_begin[y + 1] - row_room_begin[y], "row room");
        used += packed;
        first_index_[pixel] = start.first_index;
        weight_scale_[pixel] = start.scale;
        count[pixel] = static_cast<int64_t>(packed);
      }
      Report(options_.progress, {"transport", ++rows_done, height, "rows"});
    }
    std::lock_guard<std::mutex> lock(counts_mutex);
    sample_counts_ += counts;
  });
  // The rows moved down into place, in order (each row's place is at or before its room, so
  // nothing not yet moved is overwritten), and the room left over given back.
  size_t end = 0;
  for (int y = 0; y < height; ++y) {
    if (end != row_room_begin[y] && row_used[y] > 0) {
      std::memmove(packed_.data() + end, packed_.data() + row_room_begin[y],
                   row_used[y] * sizeof(TransportEntry));
    }
    end += row_used[y];
  }
  ShrinkInPlace(&packed_, end);
  row_begin_.assign(pixels + 1, 0);
  int64_t offset = 0;
  for (size_t p = 0; p < pixels; ++p) {
    row_begin_[p] = offset;
    offset += count[p];
  }
  row_begin_[pixels] = offset;
  ZBRDF_ASSERT(offset == static_cast<int64_t>(packed_.size()), "transport bookkeeping");
}

std::vector<float> ForwardModel::ProjectorRadiance(const Pattern& pattern) const {
  const ProjectorParams& p = optics_.rig().projector;
  if (pattern.width != p.lens.width || pattern.height != p.lens.height ||
      pattern.levels.size() != static_cast<size_t>(pattern.width) * pattern.height) {
    throw InputError("pattern is " + std::to_string(pattern.width) + "x" +
                     std::to_string(pattern.height) + " but the projector is " +
                     std::to_string(p.lens.width) + "x" + std::to_string(p.lens.height));
  }
  if (pattern.bit_depth != p.bit_depth) {
    throw InputError("pattern has " + std::to_string(pattern.bit_depth) +
                     " bits per level but the projector takes " + std::to_string(p.bit_depth));
  }
  const double max_level = std::ldexp(1.0, p.bit_depth) - 1;
  // Response of every level, once.
  std::vector<double> response(static_cast<size_t>(max_level) + 1);
  for (size_t level = 0; level < response.size(); ++level) {
    response[level] = p.black_level + (1 - p.black_level) * p.Response(level / max_level);
  }
  const double scale = p.peak_radiance_w_m2_sr * ProjectorPathTransmission();
  std::vector<float> radiance(pattern.levels.size());
  for (int y = 0; y < pattern.height; ++y) {
    for (int x = 0; x < pattern.width; ++x) {
      const size_t i = static_cast<size_t>(y) * pattern.width + x;
      const uint16_t level = pattern.levels[i];
      if (level > max_level) {
        throw InputError("pattern level " + std::to_string(level) + " at pixel (" +
                         std::to_string(x) + ", " + std::to_string(y) + ") exceeds " +
                         std::to_string(static_cast<int>(max_level)));
      }
      radiance[i] = static_cast<float>(scale * response[level] * p.FlatField(x + 0.5, y + 0.5));
    }
  }
  return radiance;
}

std::array<double, kFootprintMoments> ForwardModel::PatternMoments(
    const std::vector<float>& radiance) const {
  std::array<double, kFootprintMoments> moments{};
  for (size_t j = 0; j < radiance.size(); ++j) {
    if (radiance[j] == 0) continue;
    for (int k = 0; k < kFootprintMoments; ++k) {
      moments[k] +=
          static_cast<double>(maps_.projector_moments[j * kFootprintMoments + k]) * radiance[j];
    }
  }
  return moments;
}

std::vector<float> ForwardModel::ElectronRate(const Pattern& pattern) const {
  return RateOfRadiance(ProjectorRadiance(pattern));
}

std::vector<float> ForwardModel::RateOfRadiance(const std::vector<float>& radiance) const {
  const std::array<double, kFootprintMoments> moments = PatternMoments(radiance);
  const int64_t pixels = static_cast<int64_t>(row_begin_.size()) - 1;
  std::vector<float> rate(pixels, 0.0f);
  ParallelFor(pixels, 4096, [&](int64_t p0, int64_t p1) {
    for (int64_t p = p0; p < p1; ++p) {
      rate[p] = PixelRate(p, moments, RowProduct(Row(p), first_index_[p], radiance.data()));
    }
  });
  return rate;
}

std::vector<std::vector<float>> ForwardModel::ElectronRates(
    std::span<const Pattern> patterns) const {
  constexpr int kLanes = kRowProductPatterns;
  const int64_t pixels = static_cast<int64_t>(row_begin_.size()) - 1;
  std::vector<std::vector<float>> rates;
  rates.reserve(patterns.size());
  for (size_t begin = 0; begin < patterns.size(); begin += kLanes) {
    const size_t count = std::min(patterns.size() - begin, static_cast<size_t>(kLanes));
    std::vector<std::vector<float>> radiance(count);
    for (size_t i = 0; i < count; ++i) {
      try {
        radiance[i] = ProjectorRadiance(patterns[begin + i]);
      } catch (const InputError& e) {
        throw InputError("pattern " + std::to_string(begin + i + 1) + " of " +
                         std::to_string(patterns.size()) + ": " + e.what());
      }
    }
    if (count == 1) {  // one image: the gathers read 8x less than a pass of all lanes
      rates.push_back(RateOfRadiance(radiance[0]));
      continue;
    }
    // Lanes past count stay zero. 64-byte aligned, so that a pixel's lanes share a cache line;
    // in huge pages, as the rows' reads land anywhere in it (basis/huge_pages.h).
    const size_t projector_pixels = radiance[0].size();
    std::vector<float> storage;
    AssignInHugePages(&storage, projector_pixels * kLanes + 16, 0.0f);
    float* const interleaved = reinterpret_cast<float*>(
        (reinterpret_cast<uintptr_t>(storage.data()) + 63) & ~static_cast<uintptr_t>(63));
    std::vector<std::array<double, kFootprintMoments>> moments(count);
    for (size_t i = 0; i < count; ++i) {
      moments[i] = PatternMoments(radiance[i]);
      for (size_t j = 0; j < projector_pixels; ++j) interleaved[j * kLanes + i] = radiance[i][j];
    }
    const size_t first_new = rates.size();
    for (size_t i = 0; i < count; ++i) rates.emplace_back(pixels, 0.0f);
    ParallelFor(pixels, 4096, [&](int64_t p0, int64_t p1) {
      double products[kLanes];
      for (int64_t p = p0; p < p1; ++p) {
        RowProducts(Row(p), first_index_[p], interleaved, products);
        for (size_t i = 0; i < count; ++i) {
          rates[first_new + i][p] = PixelRate(p, moments[i], products[i]);
        }
      }
    });
  }
  return rates;
}

Frame ForwardModel::RenderFromRate(const std::vector<float>& electron_rate, double exposure_us,
                                   uint64_t noise_key, bool add_noise) const {
  const Rig& rig = optics_.rig();
  const SensorParams& s = rig.sensor;
  Frame frame;
  frame.width = rig.camera.width;
  frame.height = rig.camera.height;
  frame.layout = s.layout;
  frame.bit_depth = s.bit_depth;
  frame.exposure_us = exposure_us;
  frame.gain = s.gain_e_per_dn;
  frame.data.resize(electron_rate.size());
  SensorPixelModel model = SensorPixelModel::Of(s, exposure_us * 1e-6);
  model.key = HashMix(options_.seed ^ HashMix(noise_key ^ 0xf00dull));
  model.add_noise = add_noise;
  ParallelFor(static_cast<int64_t>(electron_rate.size()), 8192, [&](int64_t p0, int64_t p1) {
    RenderSensorPixels(
        std::span<const float>(electron_rate.data() + p0, static_cast<size_t>(p1 - p0)), p0, model,
        frame.data.data() + p0);
  });
  return frame;
}

}  // namespace zbrdf
