#include "acquisition/patterns.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/hash.h"
#include "basis/parallel.h"
#include "basis/png.h"
#include "basis/zonal_basis.h"
#include "rig/direction_maps.h"

namespace zbrdf {

namespace {

// Footprint points per axis: a pixel whose coarse points all fall on one side of the zone's
// edges is integrated with those; one the edge crosses gets the fine grid.
constexpr int kCoarse = 3, kFine = 16;
constexpr int kPatternCacheVersion = 4;

void HashBytes(uint64_t* h, const void* data, size_t size) { *h = Fnv1a64(data, size, *h); }

template <typename T>
void HashVector(uint64_t* h, const std::vector<T>& v) {
  HashBytes(h, v.data(), v.size() * sizeof(T));
}

// Directions across the footprint of projector pixel (x, y) on an n x n grid, by bilinear
// interpolation of the direction map (NeighbourDirections fills in missing neighbours).
void FootprintDirections(const RigCalibration& c, int x, int y, int n, std::vector<Vec3>* out) {
  Vec3 neighbour[3][3];
  NeighbourDirections(c.projector_direction, c.projector_solid_angle_sr, c.projector_width,
                      c.projector_height, x, y, neighbour);
  out->clear();
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      out->push_back(InterpolateFootprint(neighbour, (i + 0.5) / n - 0.5, (j + 0.5) / n - 0.5));
    }
  }
}

// Level whose normalized output is closest to r.
int NearestLevel(const RigCalibration& c, double r) {
  const int up = c.LevelFor(r);
  if (up == 0) return 0;
  return std::abs(c.projector_response[up] - r) <= std::abs(c.projector_response[up - 1] - r) ? up
                                                                                              : up - 1;
}

}  // namespace

uint64_t PatternKey(const CapturePlan& plan, const RigCalibration& c) {
  uint64_t h = kFnv1a64Offset;
  const double zone[2] = {plan.theta_min_rad, plan.theta_max_rad};
  HashBytes(&h, zone, sizeof(zone));
  const int ints[5] = {plan.order, c.projector_width, c.projector_height, c.projector_bit_depth,
                       kPatternCacheVersion};
  HashBytes(&h, ints, sizeof(ints));
  HashBytes(&h, &c.projector_black_fraction, sizeof(double));
  HashVector(&h, c.projector_response);
  HashVector(&h, c.projector_flat_field);
  HashVector(&h, c.projector_direction);
  HashVector(&h, c.projector_solid_angle_sr);
  return h;
}

PatternSet::PatternSet(const CapturePlan& plan, const RigCalibration& calibration,
                       const std::string& cache_dir, const ProgressCallback& progress)
    : width_(calibration.projector_width),
      height_(calibration.projector_height),
      bit_depth_(calibration.projector_bit_depth) {
  char name[64];
  std::snprintf(name, sizeof(name), "patterns-%016llx",
                static_cast<unsigned long long>(PatternKey(plan, calibration)));
  folder_ = (std::filesystem::path(cache_dir) / name).string();
  // A complete cached set lists every lobe of the plan, in order.
  std::ifstream index(folder_ + "/index.json");
  if (index) {
    try {
      const nlohmann::json j = nlohmann::json::parse(index);
      std::vector<LobePatternInfo> lobes;
      for (const auto& e : j.at("lobes")) {
        lobes.push_back({e.at("name").get<std::string>(), e.at("radiance_per_unit_z").get<double>(),
                         e.at("quantization_error").get<double>(), e.at("file").get<std::string>()});
      }
      bool complete = lobes.size() == plan.lobes.size();
      for (size_t i = 0; complete && i < lobes.size(); ++i) {
        complete = lobes[i].name == plan.lobes[i].Name() &&
                   std::filesystem::exists(folder_ + "/" + lobes[i].file);
      }
      if (complete) {
        lobes_ = std::move(lobes);
        return;
      }
    } catch (const nlohmann::json::exception&) {
      // A damaged index: compute again.
    }
  }
  Compute(plan, calibration, progress);
}

void PatternSet::Compute(const CapturePlan& plan, const RigCalibration& c,
                         const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  const ZonalBasis zb(plan.zone(), plan.order);
  const int n = zb.size();
  const int pixels = width_ * height_;
  // Index of each plan lobe's (function, sign) slot: slot 2k for Z_k+, 2k + 1 for Z_k-.
  std::vector<int> slot(plan.lobes.size(), -1);
  for (size_t i = 0; i < plan.lobes.size(); ++i) {
    const PlannedLobe& lobe = plan.lobes[i];
    if (lobe.kind == PlannedLobe::Kind::kDark) continue;
    const int k = lobe.l * lobe.l + lobe.l + lobe.m;
    slot[i] = 2 * k + (lobe.kind == PlannedLobe::Kind::kNegative ? 1 : 0);
  }
  // Footprint averages of Z^+ and Z^- per pixel and function, relative to the pixel's output.
  // Two passes keep memory to the patterns themselves: the first finds each slot's largest
  // required output (which sets its scale), the second writes the levels.
  const Zone zone = plan.zone();
  auto footprint_average = [&](int x, int y, std::vector<double>& avg, std::vector<double>& z) {
    std::vector<Vec3> dirs;
    FootprintDirections(c, x, y, kCoarse, &dirs);
    int inside = 0;
    for (const Vec3& w : dirs) inside += zone.ContainsCosTheta(w.z);
    if (inside != 0 && inside != kCoarse * kCoarse) FootprintDirections(c, x, y, kFine, &dirs);
    std::fill(avg.begin(), avg.end(), 0.0);
    for (const Vec3& w : dirs) {
      zb.Eval(w, z.data());
      for (int k = 0; k < n; ++k) {
        avg[2 * k] += std::max(0.0, z[k]);
        avg[2 * k + 1] += std::max(0.0, -z[k]);
      }
    }
    for (double& a : avg) a /= dirs.size();
  };
  std::vector<double> max_ratio(2 * n, 0.0);
  std::mutex mutex;
  ParallelFor(height_, 8, [&](int64_t y0, int64_t y1) {
    std::vector<double> avg(2 * n), z(n), local(2 * n, 0.0);
    for (int64_t y = y0; y < y1; ++y) {
      for (int x = 0; x < width_; ++x) {
        const int i = static_cast<int>(y) * width_ + x;
        if (!c.ProjectorValid(i) || c.projector_flat_field[i] <= 0) continue;
        footprint_average(x, static_cast<int>(y), avg, z);
        for (int s = 0; s < 2 * n; ++s) local[s] = std::max(local[s], avg[s] / c.projector_flat_field[i]);
      }
    }
    std::lock_guard<std::mutex> lock(mutex);
    for (int s = 0; s < 2 * n; ++s) max_ratio[s] = std::max(max_ratio[s], local[s]);
  });
  const int lobes = static_cast<int>(plan.lobes.size());
  std::vector<std::vector<uint16_t>> levels(lobes, std::vector<uint16_t>(pixels, 0));
  std::vector<double> err2(lobes, 0.0), ref2(lobes, 0.0);
  std::atomic<long> rows{0};
  ParallelFor(height_, 8, [&](int64_t y0, int64_t y1) {
    std::vector<double> avg(2 * n), z(n), e2(lobes, 0.0), r2(lobes, 0.0);
    for (int64_t y = y0; y < y1; ++y) {
      for (int x = 0; x < width_; ++x) {
        const int i = static_cast<int>(y) * width_ + x;
        if (!c.ProjectorValid(i) || c.projector_flat_field[i] <= 0) continue;
        footprint_average(x, static_cast<int>(y), avg, z);
        const double omega = c.projector_solid_angle_sr[i];
        for (int lobe = 0; lobe < lobes; ++lobe) {
          const int s = slot[lobe];
          if (s < 0 || max_ratio[s] <= 0) continue;
          // Normalized output r in [0, 1]: the brightest pixel of the slot gets 1.
          const double r = avg[s] / c.projector_flat_field[i] / max_ratio[s];
          const int level = NearestLevel(c, r);
          levels[lobe][i] = static_cast<uint16_t>(level);
          const double intended = r * c.projector_flat_field[i];
          const double realized = c.projector_response[level] * c.projector_flat_field[i];
          e2[lobe] += omega * (realized - intended) * (realized - intended);
          r2[lobe] += omega * intended * intended;
        }
      }
      Report(progress, {"patterns", ++rows, height_, "rows"});
    }
    std::lock_guard<std::mutex> lock(mutex);
    for (int lobe = 0; lobe < lobes; ++lobe) {
      err2[lobe] += e2[lobe];
      ref2[lobe] += r2[lobe];
    }
  });
  // Write the set: PNGs first, the index last (atomically), so a partial set is never trusted.
  std::error_code ec;
  std::filesystem::create_directories(folder_, ec);
  if (ec) throw InputError("cannot create pattern cache " + folder_ + ": " + ec.message());
  nlohmann::json index;
  index["zone_rad"] = {plan.theta_min_rad, plan.theta_max_rad};
  index["order"] = plan.order;
  index["lobes"] = nlohmann::json::array();
  // Each lobe's PNG encoded and written on its own (two at a time on two cores: 50 full-size
  // patterns took 0.56 s one after another), the index in lobe order afterwards.
  std::vector<LobePatternInfo> infos(lobes);
  ParallelFor(lobes, 1, [&](int64_t first, int64_t last) {
    for (int64_t lobe = first; lobe < last; ++lobe) {
      LobePatternInfo& info = infos[lobe];
      info.name = plan.lobes[lobe].Name();
      const int s = slot[lobe];
      // s * Z = peak * output: the sample radiance per unit of Z.
      info.radiance_per_unit_z =
          s >= 0 && max_ratio[s] > 0 ? c.projector_peak_radiance / max_ratio[s] : 0.0;
      info.quantization_error = ref2[lobe] > 0 ? std::sqrt(err2[lobe] / ref2[lobe]) : 0.0;
      char file[64];
      std::snprintf(file, sizeof(file), "lobe-%03d.png", static_cast<int>(lobe));
      info.file = file;
      PngImage image(width_, height_, 1, bit_depth_ <= 8 ? 8 : 16);
      std::copy(levels[lobe].begin(), levels[lobe].begin() + pixels, image.samples.begin());
      WriteFileAtomically(folder_ + "/" + file, EncodePng(image, 3));
    }
  });
  lobes_.clear();
  for (const LobePatternInfo& info : infos) {
    index["lobes"].push_back({{"name", info.name},
                              {"radiance_per_unit_z", info.radiance_per_unit_z},
                              {"quantization_error", info.quantization_error},
                              {"file", info.file}});
    lobes_.push_back(info);
  }
  WriteFileAtomically(folder_ + "/index.json", index.dump(1) + "\n");
  compute_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Pattern PatternSet::Load(int lobe) const {
  const std::string path = folder_ + "/" + lobes_.at(lobe).file;
  const auto damaged = [&path] {
    return InputError("pattern " + path +
                      " is missing or damaged; delete its folder to recompute it");
  };
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  if (!in || !(bytes << in.rdbuf())) throw damaged();
  PngImage image;
  try {
    image = DecodePng(bytes.str(), "pattern " + path);
  } catch (const InputError&) {
    throw damaged();
  }
  if (image.height != height_ || image.width != width_ || image.channels != 1) throw damaged();
  Pattern p;
  p.width = width_;
  p.height = height_;
  p.bit_depth = bit_depth_;
  p.levels = std::move(image.samples);
  return p;
}

}  // namespace zbrdf
