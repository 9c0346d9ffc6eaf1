#include "rig/direction_maps.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "basis/zone.h"
#include "tests/rig/rig_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

TEST(DirectionMapsTest, CameraMapCoversTheZoneWithUnitDirections) {
  const auto& shared = testing::SharedFastThesisRig();
  const DirectionMap& cam = shared.maps.camera;
  double theta_min = 10, theta_max = 0;
  int valid = 0, full = 0;
  for (int i = 0; i < cam.size(); ++i) {
    if (!cam.Valid(i)) continue;
    ++valid;
    if (cam.throughput[i] == 1.0f) ++full;
    const Vec3 w = cam.Direction(i);
    EXPECT_NEAR(Length(w), 1.0, 1e-6);
    theta_min = std::min(theta_min, SphericalTheta(w));
    theta_max = std::max(theta_max, SphericalTheta(w));
  }
  EXPECT_GT(full, valid * 9 / 10);
  EXPECT_NEAR(RadToDeg(theta_min), RadToDeg(shared.optics.design().zone_min_rad), 0.5);
  EXPECT_NEAR(RadToDeg(theta_max), RadToDeg(shared.optics.design().zone_max_rad), 0.5);
}

TEST(DirectionMapsTest, PixelSolidAnglesSumToTheZone) {
  // Interior pixels tile the zone's directions: the sum of their solid angles approximates the
  // zone's 2 pi (cos theta_min - cos theta_max), less the edge pixels without a neighbour pair
  // (a band about one pixel wide on each side, ~3% at the fast preset).
  const auto& shared = testing::SharedFastThesisRig();
  double sum = 0;
  for (float s : shared.maps.camera.solid_angle_sr) sum += s;
  const DomeDesign& d = shared.optics.design();
  const double zone = 2 * M_PI * (std::cos(d.zone_min_rad) - std::cos(d.zone_max_rad));
  EXPECT_NEAR(sum / zone, 1.0, 0.05);
}

TEST(DirectionMapsTest, GridLookupInvertsTheProjectorMap) {
  const auto& shared = testing::SharedFastThesisRig();
  const DirectionMap& proj = shared.maps.projector;
  int checked = 0;
  double worst = 0;
  for (int y = 0; y < proj.height; ++y) {
    for (int x = 0; x < proj.width; ++x) {
      const int i = y * proj.width + x;
      if (proj.throughput[i] < 1.0f) continue;
      // The chief ray of the pixel center lands at the sample center from this direction.
      const auto path =
          shared.optics.TraceToSample(shared.optics.projector().ChiefRay(x + 0.5, y + 0.5));
      if (path.status != OpticalSystem::PathStatus::kLanded) continue;
      double px, py;
      if (!shared.maps.grid.Lookup(path.w, &px, &py)) continue;
      worst = std::max(worst, std::hypot(px - (x + 0.5), py - (y + 0.5)));
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
  // Bilinear interpolation of a smooth map on a 0.25 deg grid: well under a pixel.
  EXPECT_LT(worst, 0.05);
}

// The grid's fixed-point unit: the finest power of two at which every coordinate on the
// projector rounds below kUncovered, the marker of a node that reaches no projector pixel.
TEST(DirectionMapsTest, GridUnitIsTheFinestPowerOfTwoThatHoldsTheProjector) {
  EXPECT_EQ(GridPixelsPerUnit(800, 600), 1.0 / 64);   // 800 * 64 = 51200
  EXPECT_EQ(GridPixelsPerUnit(600, 800), 1.0 / 64);   // the larger side decides
  EXPECT_EQ(GridPixelsPerUnit(1023, 768), 1.0 / 64);  // 65472 < 65535
  EXPECT_EQ(GridPixelsPerUnit(1024, 768), 1.0 / 32);  // 65536 would be the marker and beyond
  EXPECT_EQ(GridPixelsPerUnit(8, 8), 1.0 / 4096);     // 8 * 8192 = 65536
  EXPECT_EQ(GridPixelsPerUnit(20000, 20000), 0.5);    // the rig file's largest projector
  for (const int side : {8, 600, 800, 1023, 1024, 1920, 20000}) {
    const double unit = GridPixelsPerUnit(side, 8);
    // The largest coordinate on the projector, just below its side, rounds to a unit value...
    EXPECT_LT(std::lround(std::nextafter(static_cast<double>(side), 0.0) / unit),
              ProjectorDirectionGrid::kUncovered)
        << side;
    // ... and the next finer unit would not hold it.
    EXPECT_GE(std::lround(std::nextafter(static_cast<double>(side), 0.0) / (unit / 2)),
              ProjectorDirectionGrid::kUncovered)
        << side;
  }
}

// Each covered node holds the projector pixel coordinates of its direction's exact trace to
// within half a unit (the rounding), and the uncovered ones reach no projector pixel.
TEST(DirectionMapsTest, GridNodesAreTheTracedCoordinatesToHalfAUnit) {
  const auto& shared = testing::SharedFastThesisRig();
  const ProjectorDirectionGrid& grid = shared.maps.grid;
  const int width = shared.optics.projector().params().width;
  const int height = shared.optics.projector().params().height;
  ASSERT_EQ(grid.pixels_per_unit, GridPixelsPerUnit(width, height));
  int covered = 0, uncovered = 0;
  double worst = 0;
  for (size_t k = 0; k < grid.xy.size() / 2; k += 37) {
    const int i = static_cast<int>(k / grid.n_phi), j = static_cast<int>(k % grid.n_phi);
    const Vec3 w = SphericalDirection(std::min(i * grid.step_rad, M_PI / 2), j * grid.step_rad);
    const auto path = shared.optics.TraceFromSample({0, 0, 0}, w);
    bool on_projector = false;
    double px = 0, py = 0;
    if (path.reached) {
      const auto proj = shared.optics.projector().Project(path.at_lens);
      px = proj.px;
      py = proj.py;
      on_projector =
          proj.in_front && proj.in_aperture && px >= 0 && py >= 0 && px < width && py < height;
    }
    ASSERT_EQ(grid.Covered(k), on_projector) << "node " << k;
    if (!on_projector) {
      ++uncovered;
      continue;
    }
    ++covered;
    worst = std::max({worst, std::abs(grid.xy[2 * k] * grid.pixels_per_unit - px),
                      std::abs(grid.xy[2 * k + 1] * grid.pixels_per_unit - py)});
  }
  EXPECT_GT(covered, 1000);
  EXPECT_GT(uncovered, 1000);
  EXPECT_LE(worst, 0.5 * grid.pixels_per_unit);
}

TEST(DirectionMapsTest, CacheRoundTripsAndRejectsDamage) {
  const auto& shared = testing::SharedFastThesisRig();
  const std::string dir = testing::TestCacheDir() + "/roundtrip-" + std::to_string(::getpid());
  std::filesystem::remove_all(dir);
  const RigMaps built = LoadOrBuildRigMaps(shared.optics, dir);
  const RigMaps loaded = LoadOrBuildRigMaps(shared.optics, dir);
  EXPECT_EQ(built.camera.direction, loaded.camera.direction);
  EXPECT_EQ(built.projector.throughput, loaded.projector.throughput);
  EXPECT_EQ(built.grid.n_phi, loaded.grid.n_phi);
  // Truncate the file: the maps are rebuilt, identical.
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    std::filesystem::resize_file(entry.path(), 1000);
  }
  const RigMaps rebuilt = LoadOrBuildRigMaps(shared.optics, dir);
  EXPECT_EQ(rebuilt.camera.direction, built.camera.direction);
  // A grid size that is not the rig's (here 99999 rows): rebuilt, not trusted (nor allocated).
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    std::string bytes;
    {
      std::ifstream in(entry.path(), std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const std::string step(reinterpret_cast<const char*>(&built.grid.step_rad), sizeof(double));
    const size_t at = bytes.rfind(step);  // the grid's step, then its two sizes
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(bytes.compare(at + 8, 4, reinterpret_cast<const char*>(&built.grid.n_theta), 4), 0);
    const int32_t rows = 99999;
    bytes.replace(at + 8, 4, reinterpret_cast<const char*>(&rows), 4);
    std::ofstream(entry.path(), std::ios::binary) << bytes;
  }
  const RigMaps after_bad_size = LoadOrBuildRigMaps(shared.optics, dir);
  EXPECT_EQ(after_bad_size.grid.n_theta, built.grid.n_theta);
  ASSERT_EQ(after_bad_size.grid.xy.size(), built.grid.xy.size());
  EXPECT_EQ(after_bad_size.grid.xy, built.grid.xy);
  EXPECT_EQ(after_bad_size.grid.pixels_per_unit, built.grid.pixels_per_unit);
  std::filesystem::remove_all(dir);
}

// The maps are traced only in blocks grown from lit seed pixels (TraceDeviceMap); tracing every
// pixel (a second method, the plain loop) must give the same maps bit for bit: the thesis rig at
// the fast preset, the same rig misaligned (its lit patches moved off the middle and made
// lopsided), the full-dome rig, and the full-resolution camera, whose lit disk is 4x as many
// pixels across.
void ExpectSameMap(const DirectionMap& grown, const DirectionMap& every, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(grown.width, every.width);
  ASSERT_EQ(grown.height, every.height);
  int lit = 0;
  for (int i = 0; i < every.size(); ++i) lit += every.Valid(i);
  EXPECT_GT(lit, every.size() / 20);  // a map with something to find
  EXPECT_EQ(grown.direction, every.direction);
  EXPECT_EQ(grown.throughput, every.throughput);
  EXPECT_EQ(grown.solid_angle_sr, every.solid_angle_sr);
}

TEST(DirectionMapsTest, MapsTracedAroundTheLitPixelsAreThoseOfEveryPixel) {
  const auto& shared = testing::SharedFastThesisRig();
  const int side = static_cast<int>(std::lround(std::sqrt(shared.rig.simulation.aperture_samples)));
  ExpectSameMap(shared.maps.camera,
                TraceDeviceMapEveryPixel(shared.optics, shared.optics.camera(), side, false),
                "fast camera");
  ExpectSameMap(shared.maps.projector,
                TraceDeviceMapEveryPixel(shared.optics, shared.optics.projector(), side, true),
                "fast projector");

  Rig misaligned = shared.rig;
  misaligned.misalignment.camera_offset_mm = {0.3, -0.2, 0};
  misaligned.misalignment.camera_tilt_deg[0] = 0.5;
  misaligned.misalignment.camera_tilt_deg[1] = -0.3;
  misaligned.misalignment.projector_tilt_deg[0] = -0.4;
  misaligned.misalignment.parabola_offset_mm = {0.2, 0.1, 0};
  // The other bundled rig's dome reaches to the horizon.
  const Rig dome = ApplyPreset(LoadRig(testing::SourceRig("full-dome.yaml")), Preset::kFast);
  for (const auto& [rig, name] : {std::pair{misaligned, "misaligned"}, {dome, "full-dome"}}) {
    const OpticalSystem optics(rig);
    for (const bool projector : {false, true}) {
      const ThinLens& lens = projector ? optics.projector() : optics.camera();
      ExpectSameMap(TraceDeviceMap(optics, lens, side, projector, "map", nullptr),
                    TraceDeviceMapEveryPixel(optics, lens, side, projector),
                    std::string(name) + (projector ? " projector" : " camera"));
    }
  }

  const OpticalSystem full(LoadRig(testing::SourceRig("thesis.yaml")));
  ExpectSameMap(TraceDeviceMap(full, full.camera(), side, false, "camera map", nullptr),
                TraceDeviceMapEveryPixel(full, full.camera(), side, false), "full camera");
}

TEST(DirectionMapsTest, BayerChannels) {
  EXPECT_EQ(BayerChannel(PixelLayout::kBayerRGGB, 0, 0), 0);
  EXPECT_EQ(BayerChannel(PixelLayout::kBayerRGGB, 1, 0), 1);
  EXPECT_EQ(BayerChannel(PixelLayout::kBayerRGGB, 0, 1), 1);
  EXPECT_EQ(BayerChannel(PixelLayout::kBayerRGGB, 1, 1), 2);
  EXPECT_EQ(BayerChannel(PixelLayout::kBayerBGGR, 0, 0), 2);
  EXPECT_EQ(BayerChannel(PixelLayout::kBayerGRBG, 1, 0), 0);
  EXPECT_EQ(BayerChannel(PixelLayout::kMono, 1, 0), -1);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
