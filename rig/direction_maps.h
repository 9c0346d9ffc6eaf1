// Pixel <-> direction maps of the rig, from ray tracing through the optics.
//
// Camera map: each camera pixel's exitant direction w_r at the sample (the mean over the rays
// across its area and lens aperture that land on the sample), the solid angle its footprint
// covers in direction space, and its throughput (the fraction of those rays that land).
// Projector map: the same for projector pixels, except that the direction is the chief ray's:
// the direction the pixel lights the sample center from. Direction grid: the inverse of the
// projector map, found by tracing from the sample center outward, for "which projector pixel lights
// the sample from w". Maps are cached on disk, keyed by a hash of the rig (RigHash).
//
// These are the nominal maps of a rig description; calibration (calibration/) estimates the
// maps of a real, misaligned rig with the same types.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "basis/progress.h"
#include "basis/vec3.h"
#include "rig/optics.h"

namespace zbrdf {

struct DirectionMap {
  int width = 0, height = 0;
  std::vector<float> direction;       // 3 per pixel: mean landed direction (unit); 0 if invalid
  std::vector<float> throughput;      // fraction of pixel-area x aperture rays landing (0..1)
  std::vector<float> solid_angle_sr;  // footprint in direction space; 0 if unknown

  int size() const { return width * height; }
  bool Valid(int pixel) const { return throughput[pixel] > 0; }
  Vec3 Direction(int pixel) const {
    return {direction[3 * pixel], direction[3 * pixel + 1], direction[3 * pixel + 2]};
  }
};

// Continuous projector pixel coordinates of the ray that reaches the sample center from w, on
// a (theta, phi) grid over the upper hemisphere.
struct ProjectorDirectionGrid {
  double step_rad = 0;
  int n_theta = 0, n_phi = 0;  // nodes: theta = i * step (i < n_theta), phi = j * step
  // Projector pixel coordinates of node k = i * n_phi + j at xy[2k] (x) and xy[2k + 1] (y), in
  // fixed point: units of pixels_per_unit pixels, kUncovered where that direction does not
  // reach the projector's pixels. Interleaved, so that a lookup's four nodes are two cache
  // lines, and 16 bits, so that the lit zone's nodes take 8 MB at full resolution instead of
  // floats' 16: the transport build looks one up per sample, at random directions, and waited
  // for memory more than it computed (docs/simulator.md).
  static constexpr uint16_t kUncovered = 0xffff;
  double pixels_per_unit = 1;  // 1 / 2^k: GridPixelsPerUnit of the projector
  std::vector<uint16_t> xy;

  // 1 / step_rad, multiplied by instead of divided by in the per-sample lookups.
  double NodesPerRad() const { return n_phi * (0.5 / M_PI); }

  bool Covered(size_t node) const { return xy[2 * node] != kUncovered; }
  // Sets node k to projector pixel coordinates (px, py), which must lie on the projector
  // (0 <= px < width, 0 <= py < height): rounded to the nearest unit, within
  // pixels_per_unit / 2 (1/128 pixel for projectors up to 1023 pixels wide).
  void SetNode(size_t node, double px, double py) {
    xy[2 * node] = static_cast<uint16_t>(std::lround(px / pixels_per_unit));
    xy[2 * node + 1] = static_cast<uint16_t>(std::lround(py / pixels_per_unit));
  }

  // Bilinear interpolation of the coordinates between the four surrounding nodes; false if
  // any of them is uncovered (callers trace such directions exactly).
  bool Lookup(const Vec3& w, double* px_out, double* py_out) const;
  // The same for a direction above the horizon given by its angles (SphericalTheta and
  // SphericalPhi of w), for callers that already have them.
  // Inline: the transport build calls it for every sample.
  bool LookupAngles(double theta_rad, double phi_rad, double* px_out, double* py_out) const;
  // Asks the CPU to start fetching the nodes LookupAngles(theta_rad, phi_rad) reads (the
  // cache lines of its four nodes), for a caller that will look the direction up a little later;
  // changes nothing else. The same angles as LookupAngles. The transport build looks up random
  // directions in a grid far larger than a core's cache: a lookup waits for memory unless its
  // nodes were asked for ahead (docs/simulator.md).
  void PrefetchAngles(double theta_rad, double phi_rad) const;

  // The cell LookupAngles interpolates in: its lower node (row i, column j0) and the next
  // column's node in that row (wrapped) as node indices, and the fractions across it in theta
  // (a) and phi (b); the row above is n_phi nodes further. False beyond the last row.
  struct Cell {
    size_t n00, n01;
    double a, b;
  };
  bool CellAt(double theta_rad, double phi_rad, Cell* cell) const;
  // The coordinates of a cell's four nodes: n00, n01 and the row above's n10, n11.
  struct CellNodes {
    const uint16_t *n00, *n01, *n10, *n11;
  };
  CellNodes NodesOf(const Cell& cell) const {
    const size_t row = 2 * static_cast<size_t>(n_phi);
    const uint16_t* n00 = &xy[2 * cell.n00];
    const uint16_t* n01 = &xy[2 * cell.n01];
    return {n00, n01, n00 + row, n01 + row};
  }
};

// The grid's fixed-point unit for a projector of width x height pixels, in pixels: the smallest
// power of two 2^-k (k <= 16) for which every coordinate on the projector, rounded to units,
// stays below kUncovered (1/64 for the bundled rigs' 800 x 600).
double GridPixelsPerUnit(int width, int height);

inline bool ProjectorDirectionGrid::CellAt(double theta, double phi, Cell* cell) const {
  if (n_theta == 0) return false;
  const double nodes_per_rad = NodesPerRad();  // step_rad = 2 pi / n_phi
  const double fi = theta * nodes_per_rad, fj = phi * nodes_per_rad;
  const int i = static_cast<int>(fi), j = static_cast<int>(fj);
  if (i + 1 >= n_theta) return false;
  cell->a = fi - i;
  cell->b = fj - j;
  // phi is in [0, 2 pi] (the zone sampler's azimuth may reach 2 pi): j is at most n_phi, so
  // the wrap needs no division.
  const int j0 = j >= n_phi ? j - n_phi : j, j1 = j0 + 1 == n_phi ? 0 : j0 + 1;
  cell->n00 = static_cast<size_t>(i) * n_phi + j0;
  cell->n01 = static_cast<size_t>(i) * n_phi + j1;
  return true;
}

inline void ProjectorDirectionGrid::PrefetchAngles(double theta, double phi) const {
  Cell cell;
  if (!CellAt(theta, phi, &cell)) return;
  // The next column's nodes too: one lookup in sixteen (a node is 4 bytes) has them in the
  // next cache line, or at the row's other end, and such a lookup waited for memory.
  const auto [n00, n01, n10, n11] = NodesOf(cell);
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  // An instruction the compiler must emit: GCC 12 at -O3 deleted __builtin_prefetch and
  // _mm_prefetch here (objdump showed no prefetch left in the transport build).
  asm volatile("prefetcht0 %0" : : "m"(*n00));
  asm volatile("prefetcht0 %0" : : "m"(*n10));
  asm volatile("prefetcht0 %0" : : "m"(*n01));
  asm volatile("prefetcht0 %0" : : "m"(*n11));
#else
  __builtin_prefetch(n00);
  __builtin_prefetch(n10);
  __builtin_prefetch(n01);
  __builtin_prefetch(n11);
#endif
}

inline bool ProjectorDirectionGrid::LookupAngles(double theta, double phi, double* px_out,
                                                 double* py_out) const {
  Cell cell;
  if (!CellAt(theta, phi, &cell)) return false;
  const double a = cell.a, b = cell.b;
  const auto [n00, n01, n10, n11] = NodesOf(cell);
  if (n00[0] == kUncovered || n01[0] == kUncovered || n10[0] == kUncovered ||
      n11[0] == kUncovered) {
    return false;
  }
  const double s = pixels_per_unit;
  *px_out = s * ((1 - a) * ((1 - b) * n00[0] + b * n01[0]) + a * ((1 - b) * n10[0] + b * n11[0]));
  *py_out = s * ((1 - a) * ((1 - b) * n00[1] + b * n01[1]) + a * ((1 - b) * n10[1] + b * n11[1]));
  return true;
}

// The map of a camera or projector (`lens`, one of optics' two), traced with samples_1d^2
// rays per pixel over its area and aperture (16x at the rim); see the top of this file.
// chief_direction: a pixel's direction is its chief ray's (the projector's) instead of the
// mean of its landed rays (the camera's). Traces only the blocks of pixels around those that
// see the sample, grown from a coarse lattice of seed pixels; `progress` gets `stage` and blocks.
DirectionMap TraceDeviceMap(const OpticalSystem& optics, const ThinLens& lens, int samples_1d,
                            bool chief_direction, const std::string& stage,
                            const ProgressCallback& progress);
// The same map with every pixel traced: the reference TraceDeviceMap must equal exactly.
DirectionMap TraceDeviceMapEveryPixel(const OpticalSystem& optics, const ThinLens& lens,
                                      int samples_1d, bool chief_direction);

// Number of moments per projector pixel (see RigMaps::projector_moments).
inline constexpr int kFootprintMoments = 5;
// b_k(w) for w = (x, y, z): 1, z, z^2, x, y.
inline void FootprintBasis(const Vec3& w, double b[kFootprintMoments]) {
  b[0] = 1;
  b[1] = w.z;
  b[2] = w.z * w.z;
  b[3] = w.x;
  b[4] = w.y;
}

struct RigMaps {
  DirectionMap camera, projector;
  ProjectorDirectionGrid grid;
  // Per projector pixel j and k < kFootprintMoments: integral over the directions j lights the
  // sample center from of b_k(w) cos(theta) dw (sr), by a quadrature 8 points per pixel across.
  // The simulator integrates the smooth part of a BRDF against any pattern with these exactly.
  std::vector<float> projector_moments;
};

// Traces all maps (parallel). Deterministic.
RigMaps BuildRigMaps(const OpticalSystem& optics, const ProgressCallback& progress = nullptr);

// $ZBRDF_CACHE_DIR, else $XDG_CACHE_HOME/zbrdf, else $HOME/.cache/zbrdf, else /tmp/zbrdf-cache.
std::string DefaultCacheDir();

// Loads the maps for this rig from cache_dir, or builds and stores them there (atomically).
// A cache file that is unreadable or from another rig is rebuilt, never trusted.
RigMaps LoadOrBuildRigMaps(const OpticalSystem& optics, const std::string& cache_dir,
                           const ProgressCallback& progress = nullptr);

// The directions of pixel (x, y) and its 8 neighbours, out[1 + dy][1 + dx], from a direction
// map (3 floats per pixel; a pixel is valid where valid_if_positive > 0). A missing neighbour
// is extrapolated linearly from the opposite side (2 c - opposite), or, with neither, taken as
// the center's; so a footprint at the edge of the map keeps its true size.
void NeighbourDirections(const std::vector<float>& direction,
                         const std::vector<float>& valid_if_positive, int width, int height, int x,
                         int y, Vec3 out[3][3]);
// Direction at offset (fx, fy) in [-0.5, 0.5]^2 pixels from the center, bilinear between the
// center and its neighbours.
Vec3 InterpolateFootprint(const Vec3 neighbours[3][3], double fx, double fy);

// Bayer channel (0 R, 1 G, 2 B) of a camera pixel; -1 for mono sensors.
int BayerChannel(PixelLayout layout, int x, int y);

}  // namespace zbrdf
