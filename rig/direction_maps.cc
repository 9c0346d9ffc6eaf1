#include "rig/direction_maps.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/huge_pages.h"
#include "basis/parallel.h"

namespace zbrdf {

namespace {

// 9: the grid's coordinates interleaved; 10: dome hits by false position; 11: the grid's
// coordinates in 16-bit fixed point.
constexpr uint32_t kMapsCacheVersion = 11;

// Device maps are traced in blocks of kMapBlock x kMapBlock pixels grown from seeds one per
// kMapSeedStep x kMapSeedStep pixels (TraceDeviceMap).
constexpr int kMapBlock = 16;
constexpr int kMapSeedStep = 4;

// Traces one pixel of a device map: stratified rays over the pixel area and the aperture; a
// pixel that is partly lit (at the rim of the mirrors or of the sample) is traced again with
// 16x the rays, since its throughput scales its signal directly. Writes the pixel's direction
// and throughput (left 0 where no ray lands) and returns whether any ray landed.
// chief_direction: a pixel's direction is that of its chief ray where it lands (the projector:
// the direction it lights the sample center from), else the mean of its landed rays (the
// camera: what the pixel averages over its aperture).
bool TraceMapPixel(const OpticalSystem& optics, const ThinLens& lens, int samples_1d,
                   bool chief_direction, int x, int y, DirectionMap* map) {
  Vec3 sum{0, 0, 0};
  int landed = 0, samples = 0;
  for (int pass = 0; pass < 2; ++pass) {
    const int side = pass == 0 ? samples_1d : 4 * samples_1d;
    sum = {0, 0, 0};
    landed = 0;
    samples = side * side;
    for (int s = 0; s < samples; ++s) {
      // Aperture on a side x side grid; the pixel area on a second grid, paired by a fixed
      // permutation, both symmetric about the center so that the mean direction is the
      // center's.
      const double u0 = (s % side + 0.5) / side;
      const double u1 = (s / side + 0.5) / side;
      const int t = (s * 7 + 3) % samples;
      const double jx = (t % side + 0.5) / side;
      const double jy = (t / side + 0.5) / side;
      const auto path =
          optics.TraceToSample(lens.GenerateRay(x + jx, y + jy, samples > 1 ? u0 : -1, u1));
      if (path.status != OpticalSystem::PathStatus::kLanded) continue;
      sum += path.w;
      ++landed;
    }
    if (landed == 0 || landed == samples) break;
  }
  if (landed == 0) return false;
  const int index = y * map->width + x;
  Vec3 w = Normalize(sum);
  if (chief_direction) {
    const auto chief = optics.TraceToSample(lens.ChiefRay(x + 0.5, y + 0.5));
    if (chief.status == OpticalSystem::PathStatus::kLanded) w = chief.w;
  }
  map->direction[3 * index] = static_cast<float>(w.x);
  map->direction[3 * index + 1] = static_cast<float>(w.y);
  map->direction[3 * index + 2] = static_cast<float>(w.z);
  map->throughput[index] = static_cast<float>(landed) / samples;
  return true;
}

DirectionMap EmptyMap(const ThinLensParams& p) {
  DirectionMap map;
  map.width = p.width;
  map.height = p.height;
  map.direction.assign(3 * map.size(), 0.0f);
  map.throughput.assign(map.size(), 0.0f);
  map.solid_angle_sr.assign(map.size(), 0.0f);
  return map;
}

// Solid angle of each pixel from central differences of its neighbours' directions.
void FillSolidAngles(DirectionMap* map_out) {
  DirectionMap& map = *map_out;
  const int width = map.width, height = map.height;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int i = y * width + x;
      if (!map.Valid(i)) continue;
      auto neighbour = [&](int nx, int ny, Vec3* out) {
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) return false;
        const int j = ny * width + nx;
        if (!map.Valid(j)) return false;
        *out = map.Direction(j);
        return true;
      };
      Vec3 l, r, d, u;
      const Vec3 c = map.Direction(i);
      const bool hl = neighbour(x - 1, y, &l), hr = neighbour(x + 1, y, &r);
      const bool hd = neighbour(x, y - 1, &d), hu = neighbour(x, y + 1, &u);
      if ((!hl && !hr) || (!hd && !hu)) continue;
      const Vec3 dx = hl && hr ? (r - l) * 0.5 : (hr ? r - c : c - l);
      const Vec3 dy = hd && hu ? (u - d) * 0.5 : (hu ? u - c : c - d);
      map.solid_angle_sr[i] = static_cast<float>(Length(Cross(dx, dy)));
    }
  }
}

// Calls trace(x, y), which returns whether the pixel is lit, for the pixels of a width x height
// image that can be lit, sparing most of the others. Only the pixels that see the sample hold
// anything in a device map (a fifth of the thesis camera's), so the image is traced in blocks
// grown from seeds: the pixels of a coarse lattice are traced first, every block holding a lit one
// is traced whole, and a block whose lit pixels reach its edge makes the blocks across that
// edge (and corner) traced next, until no block is added. Every lit pixel that is connected
// (8-neighbours) to a lit lattice pixel through lit pixels is reached, since such a chain leaves
// a block only through a lit edge pixel; a pixel is traced exactly as one by one, so the image
// is the same. Only a lit patch narrower than the lattice everywhere and apart from the rest
// could be missed (tests/rig/direction_maps_test.cc compares with tracing every pixel).
// trace is called at most once per pixel, from several threads at once for different pixels.
template <typename Trace>
void TraceAroundLit(int width, int height, const std::string& stage,
                    const ProgressCallback& progress, const Trace& trace) {
  const int blocks_x = (width + kMapBlock - 1) / kMapBlock;
  const int blocks_y = (height + kMapBlock - 1) / kMapBlock;
  std::vector<uint8_t> block_state(static_cast<size_t>(blocks_x) * blocks_y, 0);  // 1: queued
  // Per pixel: 0 not traced, 1 traced and dark, 2 traced and lit.
  std::vector<uint8_t> state(static_cast<size_t>(width) * height, 0);
  auto lit_at = [&](int x, int y) {
    uint8_t& s = state[static_cast<size_t>(y) * width + x];
    if (s == 0) s = trace(x, y) ? 2 : 1;
    return s == 2;
  };
  std::vector<int> queue;
  auto enqueue = [&](int bx, int by) {
    if (bx < 0 || by < 0 || bx >= blocks_x || by >= blocks_y) return;
    uint8_t& s = block_state[static_cast<size_t>(by) * blocks_x + bx];
    if (s == 0) {
      s = 1;
      queue.push_back(by * blocks_x + bx);
    }
  };
  // Seeds: one pixel in kMapSeedStep x kMapSeedStep, at the center of its cell.
  const int seeds_x = (width + kMapSeedStep - 1) / kMapSeedStep;
  const int seeds_y = (height + kMapSeedStep - 1) / kMapSeedStep;
  auto seed_x = [&](int i) { return std::min(width - 1, i * kMapSeedStep + kMapSeedStep / 2); };
  auto seed_y = [&](int j) { return std::min(height - 1, j * kMapSeedStep + kMapSeedStep / 2); };
  std::atomic<long> done{0};
  const long total_seeds = static_cast<long>(seeds_y);
  ParallelFor(seeds_y, 4, [&](int64_t j0, int64_t j1) {
    for (int64_t j = j0; j < j1; ++j) {
      for (int i = 0; i < seeds_x; ++i) lit_at(seed_x(i), seed_y(static_cast<int>(j)));
      Report(progress, {stage + " seeds", ++done, total_seeds, "rows"});
    }
  });
  for (int j = 0; j < seeds_y; ++j) {
    for (int i = 0; i < seeds_x; ++i) {
      const int x = seed_x(i), y = seed_y(j);
      if (state[static_cast<size_t>(y) * width + x] == 2) enqueue(x / kMapBlock, y / kMapBlock);
    }
  }
  long known = 0;  // blocks traced or queued: the progress's total, as far as it is known
  done = 0;
  while (!queue.empty()) {
    std::sort(queue.begin(), queue.end());
    known += static_cast<long>(queue.size());
    // The neighbours each block of this round asks for (bits: left, right, top, bottom, then
    // the corners top-left, top-right, bottom-left, bottom-right).
    std::vector<uint8_t> asks(queue.size(), 0);
    ParallelFor(static_cast<int64_t>(queue.size()), 1, [&](int64_t q0, int64_t q1) {
      for (int64_t q = q0; q < q1; ++q) {
        const int x0 = queue[q] % blocks_x * kMapBlock, y0 = queue[q] / blocks_x * kMapBlock;
        const int x1 = std::min(width, x0 + kMapBlock), y1 = std::min(height, y0 + kMapBlock);
        uint8_t ask = 0;
        for (int y = y0; y < y1; ++y) {
          for (int x = x0; x < x1; ++x) {
            if (!lit_at(x, y)) continue;
            const bool left = x == x0, right = x == x1 - 1, top = y == y0, bottom = y == y1 - 1;
            ask |= (left ? 1 : 0) | (right ? 2 : 0) | (top ? 4 : 0) | (bottom ? 8 : 0) |
                   (left && top ? 16 : 0) | (right && top ? 32 : 0) | (left && bottom ? 64 : 0) |
                   (right && bottom ? 128 : 0);
          }
        }
        asks[q] = ask;
        Report(progress, {stage, ++done, known, "blocks"});
      }
    });
    std::vector<int> round;
    round.swap(queue);
    static constexpr int kDx[8] = {-1, 1, 0, 0, -1, 1, -1, 1};
    static constexpr int kDy[8] = {0, 0, -1, 1, -1, -1, 1, 1};
    for (size_t q = 0; q < round.size(); ++q) {
      for (int k = 0; k < 8; ++k) {
        if (asks[q] & (1 << k)) enqueue(round[q] % blocks_x + kDx[k], round[q] / blocks_x + kDy[k]);
      }
    }
  }
  Report(progress, {stage, known, known, "blocks"});
}

}  // namespace

DirectionMap TraceDeviceMapEveryPixel(const OpticalSystem& optics, const ThinLens& lens,
                                      int samples_1d, bool chief_direction) {
  DirectionMap map = EmptyMap(lens.params());
  ParallelFor(map.height, 4, [&](int64_t y0, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y) {
      for (int x = 0; x < map.width; ++x) {
        TraceMapPixel(optics, lens, samples_1d, chief_direction, x, static_cast<int>(y), &map);
      }
    }
  });
  FillSolidAngles(&map);
  return map;
}

DirectionMap TraceDeviceMap(const OpticalSystem& optics, const ThinLens& lens, int samples_1d,
                            bool chief_direction, const std::string& stage,
                            const ProgressCallback& progress) {
  DirectionMap map = EmptyMap(lens.params());
  TraceAroundLit(map.width, map.height, stage, progress, [&](int x, int y) {
    return TraceMapPixel(optics, lens, samples_1d, chief_direction, x, y, &map);
  });
  FillSolidAngles(&map);
  return map;
}

namespace {

// The grid's step and node counts for a requested step in degrees (an exact period in phi), and
// its unit for a projector of width x height pixels.
ProjectorDirectionGrid GridLayout(double step_deg, int width, int height) {
  ProjectorDirectionGrid grid;
  grid.pixels_per_unit = GridPixelsPerUnit(width, height);
  grid.n_phi = static_cast<int>(std::lround(360.0 / step_deg));
  grid.step_rad = 2 * M_PI / grid.n_phi;
  grid.n_theta = static_cast<int>(std::ceil((M_PI / 2) / grid.step_rad)) + 1;
  return grid;
}

ProjectorDirectionGrid TraceGrid(const OpticalSystem& optics, double step_deg,
                                 const ProgressCallback& progress) {
  const ThinLens& projector = optics.projector();
  const int width = projector.params().width, height = projector.params().height;
  ProjectorDirectionGrid grid = GridLayout(step_deg, width, height);
  const size_t n = static_cast<size_t>(grid.n_theta) * grid.n_phi;
  // Huge pages: the transport build looks up random directions (basis/huge_pages.h).
  AssignInHugePages(&grid.xy, 2 * n, ProjectorDirectionGrid::kUncovered);
  std::atomic<long> done{0};
  ParallelFor(grid.n_theta, 8, [&](int64_t i0, int64_t i1) {
    for (int64_t i = i0; i < i1; ++i) {
      const double theta = std::min(i * grid.step_rad, M_PI / 2);
      for (int j = 0; j < grid.n_phi; ++j) {
        const Vec3 w = SphericalDirection(theta, j * grid.step_rad);
        const auto path = optics.TraceFromSample({0, 0, 0}, w);
        if (!path.reached) continue;
        const auto proj = projector.Project(path.at_lens);
        if (!proj.in_front || !proj.in_aperture) continue;
        if (proj.px < 0 || proj.py < 0 || proj.px >= width || proj.py >= height) continue;
        const size_t k = static_cast<size_t>(i) * grid.n_phi + j;
        grid.SetNode(k, proj.px, proj.py);
      }
      Report(progress, {"grid", ++done, grid.n_theta, "rows"});
    }
  });
  return grid;
}

// Moments of each projector pixel's footprint in directions (see RigMaps), by a midpoint rule
// in (cos theta, phi) with about 8 nodes across a pixel, over the lit directions.
std::vector<float> FootprintMoments(const OpticalSystem& optics, const DirectionMap& projector,
                                    const ProjectorDirectionGrid& grid,
                                    const ProgressCallback& progress) {
  const int width = projector.width, height = projector.height;
  std::vector<double> sizes;
  double theta_lo = M_PI, theta_hi = 0;
  for (int i = 0; i < projector.size(); ++i) {
    if (!projector.Valid(i) || projector.solid_angle_sr[i] <= 0) continue;
    sizes.push_back(std::sqrt(projector.solid_angle_sr[i]));
    const double theta = SphericalTheta(projector.Direction(i));
    theta_lo = std::min(theta_lo, theta);
    theta_hi = std::max(theta_hi, theta);
  }
  std::vector<float> moments(static_cast<size_t>(projector.size()) * kFootprintMoments, 0.0f);
  if (sizes.empty()) return moments;
  std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 10, sizes.end());
  const double step = sizes[sizes.size() / 10] / 8;  // the smaller pixels set the spacing
  // Pad by a few pixels: the lit set's edge is found node by node.
  theta_lo = std::max(0.0, theta_lo - 4 * sizes[sizes.size() / 10] - 2 * grid.step_rad);
  theta_hi = std::min(M_PI / 2, theta_hi + 4 * sizes[sizes.size() / 10] + 2 * grid.step_rad);
  const double cos_hi = std::cos(theta_lo), cos_lo = std::cos(theta_hi);
  const int rows = std::max(1, static_cast<int>(std::ceil((theta_hi - theta_lo) / step)));
  const double dcos = (cos_hi - cos_lo) / rows;
  std::atomic<long> done{0};
  std::vector<double> total(moments.size(), 0.0);
  std::mutex mutex;
  ParallelFor(rows, std::max(16, rows / 16), [&](int64_t r0, int64_t r1) {
    std::vector<double> local(moments.size(), 0.0);
    for (int64_t r = r0; r < r1; ++r) {
      const double z = cos_hi - (r + 0.5) * dcos;
      const double s = std::sqrt(std::max(0.0, 1 - z * z));
      const int nodes = std::max(16, static_cast<int>(std::ceil(2 * M_PI * s / step)));
      const double dphi = 2 * M_PI / nodes;
      for (int n = 0; n < nodes; ++n) {
        const double phi = (n + 0.5) * dphi;
        const Vec3 w{s * std::cos(phi), s * std::sin(phi), z};
        double px, py;
        if (!grid.Lookup(w, &px, &py)) {
          const auto path = optics.TraceFromSample({0, 0, 0}, w);
          if (!path.reached) continue;
          const auto proj = optics.projector().Project(path.at_lens);
          if (!proj.in_front || !proj.in_aperture) continue;
          px = proj.px;
          py = proj.py;
        }
        if (px < 0 || py < 0 || px >= width || py >= height) continue;
        const size_t j = static_cast<size_t>(py) * width + static_cast<size_t>(px);
        double b[kFootprintMoments];
        FootprintBasis(w, b);
        const double weight = dcos * dphi * z;
        for (int k = 0; k < kFootprintMoments; ++k) local[j * kFootprintMoments + k] += weight * b[k];
      }
      Report(progress, {"moments", ++done, rows, "rows"});
    }
    std::lock_guard<std::mutex> lock(mutex);
    for (size_t i = 0; i < local.size(); ++i) total[i] += local[i];
  });
  for (size_t i = 0; i < total.size(); ++i) moments[i] = static_cast<float>(total[i]);
  return moments;
}

template <typename T>
bool ReadVector(std::ifstream& in, std::vector<T>* v, uint64_t max_elements) {
  uint64_t n = 0;
  if (!in.read(reinterpret_cast<char*>(&n), sizeof(n)) || n > max_elements) return false;
  v->resize(n);
  return static_cast<bool>(
      in.read(reinterpret_cast<char*>(v->data()), static_cast<std::streamsize>(n * sizeof(T))));
}

bool ReadMap(std::ifstream& in, DirectionMap* m) {
  int32_t dims[2];
  if (!in.read(reinterpret_cast<char*>(dims), sizeof(dims))) return false;
  if (dims[0] <= 0 || dims[1] <= 0 || dims[0] > 20000 || dims[1] > 20000) return false;
  m->width = dims[0];
  m->height = dims[1];
  const uint64_t n = static_cast<uint64_t>(m->width) * m->height;
  return ReadVector(in, &m->direction, 3 * n) && m->direction.size() == 3 * n &&
         ReadVector(in, &m->throughput, n) && m->throughput.size() == n &&
         ReadVector(in, &m->solid_angle_sr, n) && m->solid_angle_sr.size() == n;
}

}  // namespace

double GridPixelsPerUnit(int width, int height) {
  // Coordinates are below max(width, height); rounded, at most that many units.
  const double most = std::max({width, height, 1});
  int k = 0;
  while (k < 16 && std::ldexp(most, k + 1) < ProjectorDirectionGrid::kUncovered) ++k;
  return std::ldexp(1.0, -k);
}

bool ProjectorDirectionGrid::Lookup(const Vec3& w, double* px_out, double* py_out) const {
  if (w.z <= 0 || n_theta == 0) return false;
  return LookupAngles(SphericalTheta(w), SphericalPhi(w), px_out, py_out);
}

RigMaps BuildRigMaps(const OpticalSystem& optics, const ProgressCallback& progress) {
  const Rig& rig = optics.rig();
  const int samples_1d =
      std::max(1, static_cast<int>(std::lround(std::sqrt(rig.simulation.aperture_samples))));
  RigMaps maps;
  maps.camera =
      TraceDeviceMap(optics, optics.camera(), samples_1d, false, "camera map", progress);
  maps.projector =
      TraceDeviceMap(optics, optics.projector(), samples_1d, true, "projector map", progress);
  maps.grid = TraceGrid(optics, rig.simulation.direction_grid_deg, progress);
  maps.projector_moments = FootprintMoments(optics, maps.projector, maps.grid, progress);
  return maps;
}

std::string DefaultCacheDir() {
  if (const char* dir = std::getenv("ZBRDF_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/zbrdf";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/zbrdf";
  return "/tmp/zbrdf-cache";
}

RigMaps LoadOrBuildRigMaps(const OpticalSystem& optics, const std::string& cache_dir,
                           const ProgressCallback& progress) {
  // Keyed by every field of the rig that the maps depend on: all but the transport's samples
  // per pixel, so that a simulation with another sample count (zbrdf simulate
  // --samples-per-pixel) reads the same maps.
  Rig key_rig = optics.rig();
  key_rig.simulation.samples_per_pixel = 0;
  const uint64_t hash = RigHash(key_rig);
  char name[64];
  std::snprintf(name, sizeof(name), "maps-%016llx-v%u.bin", static_cast<unsigned long long>(hash),
                kMapsCacheVersion);
  const std::filesystem::path path = std::filesystem::path(cache_dir) / name;
  {
    std::ifstream in(path, std::ios::binary);
    if (in) {
      char magic[8];
      uint64_t stored_hash = 0;
      RigMaps maps;
      // The grid this rig's step gives: a file with another is damaged (the hash covers the step).
      maps.grid = GridLayout(optics.rig().simulation.direction_grid_deg,
                             optics.projector().params().width, optics.projector().params().height);
      double step = 0;
      int32_t grid_dims[2];
      if (in.read(magic, 8) && std::memcmp(magic, "ZBRDFMAP", 8) == 0 &&
          in.read(reinterpret_cast<char*>(&stored_hash), sizeof(stored_hash)) &&
          stored_hash == hash && ReadMap(in, &maps.camera) && ReadMap(in, &maps.projector) &&
          in.read(reinterpret_cast<char*>(&step), sizeof(step)) &&
          in.read(reinterpret_cast<char*>(grid_dims), sizeof(grid_dims)) &&
          step == maps.grid.step_rad && grid_dims[0] == maps.grid.n_theta &&
          grid_dims[1] == maps.grid.n_phi) {
        const uint64_t n = static_cast<uint64_t>(grid_dims[0]) * grid_dims[1];
        // As TraceGrid's, in huge pages; ReadVector keeps the memory for a file of this size.
        AssignInHugePages(&maps.grid.xy, 2 * n, uint16_t{0});
        if (ReadVector(in, &maps.grid.xy, 2 * n) && maps.grid.xy.size() == 2 * n &&
            ReadVector(in, &maps.projector_moments,
                       static_cast<uint64_t>(maps.projector.size()) * kFootprintMoments) &&
            maps.projector_moments.size() ==
                static_cast<size_t>(maps.projector.size()) * kFootprintMoments &&
            maps.camera.width == optics.camera().params().width &&
            maps.projector.width == optics.projector().params().width) {
          return maps;
        }
      }
    }
  }
  RigMaps maps = BuildRigMaps(optics, progress);
  // The file's bytes straight from the maps (73 MB at full resolution): serialized into a
  // stream, copied out of it and written with fsync, they cost a second of a cold simulation
  // before the transport could start. A cache entry needs no fsync (WriteCacheFile: one lost
  // to a power cut is rebuilt, and a reader sees a whole entry or none), and an unwritable
  // cache only costs time.
  const int32_t grid_dims[2] = {maps.grid.n_theta, maps.grid.n_phi};
  const int32_t camera_dims[2] = {maps.camera.width, maps.camera.height};
  const int32_t projector_dims[2] = {maps.projector.width, maps.projector.height};
  std::deque<uint64_t> sizes;  // each vector's element count, as ReadVector reads it (stable)
  std::vector<std::string_view> parts = {std::string_view("ZBRDFMAP", 8), ObjectBytes(&hash)};
  auto vector = [&](const auto& v) {
    sizes.push_back(v.size());
    parts.push_back(ObjectBytes(&sizes.back()));
    parts.push_back(ObjectBytes(v));
  };
  for (const auto& [m, dims] : {std::pair{&maps.camera, camera_dims},
                                std::pair{&maps.projector, projector_dims}}) {
    parts.push_back(ObjectBytes(dims, 2));
    vector(m->direction);
    vector(m->throughput);
    vector(m->solid_angle_sr);
  }
  parts.push_back(ObjectBytes(&maps.grid.step_rad));
  parts.push_back(ObjectBytes(grid_dims, 2));
  vector(maps.grid.xy);
  vector(maps.projector_moments);
  WriteCacheFile(path.string(), parts);
  return maps;
}

void NeighbourDirections(const std::vector<float>& direction,
                         const std::vector<float>& valid_if_positive, int width, int height, int x,
                         int y, Vec3 out[3][3]) {
  auto at = [&](int px, int py, Vec3* d) {
    if (px < 0 || py < 0 || px >= width || py >= height) return false;
    const size_t i = static_cast<size_t>(py) * width + px;
    if (!(valid_if_positive[i] > 0)) return false;
    *d = {direction[3 * i], direction[3 * i + 1], direction[3 * i + 2]};
    return true;
  };
  bool have[3][3];
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) have[dy + 1][dx + 1] = at(x + dx, y + dy, &out[dy + 1][dx + 1]);
  }
  const Vec3 c = out[1][1];
  // Edge neighbours first (from the opposite edge neighbour), then corners (from the two
  // adjacent edges: c + (e1 - c) + (e2 - c)).
  for (auto [dy, dx] : {std::pair{0, -1}, {0, 1}, {-1, 0}, {1, 0}}) {
    if (have[1 + dy][1 + dx]) continue;
    out[1 + dy][1 + dx] = have[1 - dy][1 - dx] ? Normalize(2 * c - out[1 - dy][1 - dx]) : c;
  }
  for (int dy : {-1, 1}) {
    for (int dx : {-1, 1}) {
      if (have[1 + dy][1 + dx]) continue;
      out[1 + dy][1 + dx] = Normalize(out[1][1 + dx] + out[1 + dy][1] - c);
    }
  }
}

Vec3 InterpolateFootprint(const Vec3 n[3][3], double fx, double fy) {
  const int sx = fx < 0 ? -1 : 1, sy = fy < 0 ? -1 : 1;
  const double ax = std::abs(fx), ay = std::abs(fy);
  return Normalize(n[1][1] * ((1 - ax) * (1 - ay)) + n[1][1 + sx] * (ax * (1 - ay)) +
                   n[1 + sy][1] * ((1 - ax) * ay) + n[1 + sy][1 + sx] * (ax * ay));
}

int BayerChannel(PixelLayout layout, int x, int y) {
  const int odd_x = x & 1, odd_y = y & 1;
  // Channel of the 2x2 cell position (row, col) for each pattern, as named row-major.
  auto pick = [&](const char* pattern) {
    const char c = pattern[odd_y * 2 + odd_x];
    return c == 'R' ? 0 : (c == 'G' ? 1 : 2);
  };
  switch (layout) {
    case PixelLayout::kBayerRGGB: return pick("RGGB");
    case PixelLayout::kBayerGRBG: return pick("GRBG");
    case PixelLayout::kBayerGBRG: return pick("GBRG");
    case PixelLayout::kBayerBGGR: return pick("BGGR");
    default: return -1;
  }
}

}  // namespace zbrdf
