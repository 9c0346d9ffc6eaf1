#include "rig/optics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "basis/zone.h"
#include "tests/rig/rig_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// Largest |angle of incidence - angle of reflection| along a traced camera path, and the landing
// point. Re-traces the path bounce by bounce with the public intersection routines.
struct Bounces {
  bool landed = false;
  double reflection_error = 0;
  Vec3 landing;
};

Bounces TraceAndCheck(const OpticalSystem& optics, const Ray& ray) {
  Bounces b;
  bool from_above = false;
  const auto p = optics.parabola().Intersect(ray, 1e-7, &from_above);
  if (!p || !from_above) return b;
  const Vec3 d1 = Normalize(Reflect(ray.direction, p->normal));
  auto angle_error = [](const Vec3& in, const Vec3& out, const Vec3& n) {
    return std::abs(std::acos(std::clamp(-Dot(in, n), -1.0, 1.0)) -
                    std::acos(std::clamp(Dot(out, n), -1.0, 1.0)));
  };
  b.reflection_error = angle_error(ray.direction, d1, p->normal);
  // Coplanarity: the normal lies in the plane of the two rays.
  b.reflection_error = std::max(b.reflection_error, std::abs(Dot(Cross(ray.direction, d1), p->normal)));
  const auto d = optics.dome().Intersect({p->point, d1}, 1e-7);
  if (!d) return b;
  const Vec3 d2 = Normalize(Reflect(d1, d->normal));
  b.reflection_error = std::max(b.reflection_error, angle_error(d1, d2, d->normal));
  if (d2.z >= 0) return b;
  b.landing = d->point + d2 * (-d->point.z / d2.z);
  b.landed = true;
  return b;
}

TEST(OpticsTest, ChiefRaysObeyTheLawOfReflectionAndLandOnTheSampleCenter) {
  // Full-resolution thesis rig: every 8th pixel.
  const Rig rig = LoadRig(testing::SourceRig("thesis.yaml"));
  const OpticalSystem optics(rig);
  int landed = 0;
  double worst_distance = 0, worst_reflection = 0;
  for (int y = 0; y < rig.camera.height; y += 8) {
    for (int x = 0; x < rig.camera.width; x += 8) {
      const Bounces b = TraceAndCheck(optics, optics.camera().ChiefRay(x + 0.5, y + 0.5));
      if (!b.landed) continue;
      ++landed;
      worst_distance = std::max(worst_distance, Length(b.landing));
      worst_reflection = std::max(worst_reflection, b.reflection_error);
    }
  }
  EXPECT_GT(landed, 2000);
  EXPECT_LE(worst_reflection, 1e-9);
  // The dome is designed for the camera's center of projection: chief rays come back to the
  // sample center (design steps 20000: measured 3e-7 mm).
  EXPECT_LE(worst_distance, 0.1);
}

TEST(OpticsTest, ParaboloidHitsLieOnTheSurfaceWithTheGradientAsNormal) {
  ParabolaParams p;
  Misalignment none;
  const Paraboloid parabola(p, none);
  for (double x : {-10.0, -3.0, 0.0, 5.0, 12.0}) {
    const Ray ray{{x, 2.0, 300.0}, Normalize(Vec3{0.01, -0.02, -1})};
    bool above = false;
    const auto hit = parabola.Intersect(ray, 0, &above);
    ASSERT_TRUE(hit.has_value());
    EXPECT_TRUE(above);
    const Vec3 q = hit->point;
    const double r2 = q.x * q.x + q.y * q.y;
    EXPECT_NEAR(q.z, p.vertex_height_mm - r2 / (4 * p.focal_length_mm), 1e-10);
    const Vec3 expected = Normalize(Vec3{q.x / (2 * p.focal_length_mm), q.y / (2 * p.focal_length_mm), 1});
    EXPECT_NEAR(Length(hit->normal - expected), 0, 1e-12);
  }
  // Beyond the rim: no hit.
  bool above = false;
  EXPECT_FALSE(parabola.Intersect({{30, 0, 300}, {0, 0, -1}}, 0, &above).has_value());
}

TEST(OpticsTest, DomeHitsLieOnTheDesignedProfile) {
  const Rig rig = LoadRig(testing::SourceRig("full-dome.yaml"));
  const OpticalSystem optics(rig);
  const auto& profile = optics.design().profile;
  for (int k = 0; k < 200; ++k) {
    const Vec3 w = SphericalDirection(DegToRad(10 + 0.39 * k), 0.1 * k);
    const auto hit = optics.dome().Intersect({{0, 0, 0}, w}, 1e-9);
    ASSERT_TRUE(hit.has_value()) << k;
    const double r = std::hypot(hit->point.x, hit->point.y), z = hit->point.z;
    // Profile radius at height z by linear interpolation between design points.
    size_t i = 1;
    while (i + 1 < profile.size() && profile[i].z_mm < z) ++i;
    const double t = (z - profile[i - 1].z_mm) / (profile[i].z_mm - profile[i - 1].z_mm);
    const double r_profile = profile[i - 1].r_mm + t * (profile[i].r_mm - profile[i - 1].r_mm);
    EXPECT_NEAR(r, r_profile, 1e-9) << k;
    // The ray from the sample center meets the mirror on its reflecting side.
    EXPECT_LT(Dot(w, hit->normal), 0) << k;
  }
}

// An independent reference for the dome's exit: the profile radius by a search of the design
// points, the first sign change of rho - radius marched in 0.1 mm steps from the ray's entry
// into the dome's height range, then 200 bisection steps. The dome's own search starts from a
// quadric fit and refines on the segments' cones (a concave profile) or brackets the root by
// false position; both end on one segment's exact cone.
struct ReferenceExit {
  bool hit = false;
  double t = 0;
};

double ProfileRadius(const std::vector<DomeProfilePoint>& profile, double z) {
  size_t lo = 0, hi = profile.size() - 1;
  while (hi - lo > 1) {
    const size_t mid = (lo + hi) / 2;
    (profile[mid].z_mm <= z ? lo : hi) = mid;
  }
  const double u = (z - profile[lo].z_mm) / (profile[hi].z_mm - profile[lo].z_mm);
  return profile[lo].r_mm + u * (profile[hi].r_mm - profile[lo].r_mm);
}

ReferenceExit MarchToExit(const std::vector<DomeProfilePoint>& profile, const Ray& ray,
                          double t_min) {
  const double z_lo = profile.front().z_mm, z_hi = profile.back().z_mm;
  const Vec3 &o = ray.origin, &d = ray.direction;
  const double ta = (z_lo - o.z) / d.z, tb = (z_hi - o.z) / d.z;
  const double t0 = std::max(t_min, std::min(ta, tb)), t1 = std::max(ta, tb);
  auto g = [&](double t) {
    const Vec3 p = ray.At(t);
    return std::hypot(p.x, p.y) - ProfileRadius(profile, std::clamp(p.z, z_lo, z_hi));
  };
  ReferenceExit exit;
  if (!(t0 < t1) || g(t0) > 0) return exit;
  const int steps = static_cast<int>(std::ceil((t1 - t0) / 0.1));
  for (int i = 1; i <= steps; ++i) {
    double a = t0 + (i - 1) * (t1 - t0) / steps, b = t0 + i * (t1 - t0) / steps;
    if (g(b) < 0) continue;
    for (int k = 0; k < 200; ++k) (g(0.5 * (a + b)) < 0 ? a : b) = 0.5 * (a + b);
    exit.hit = true;
    exit.t = 0.5 * (a + b);
    return exit;
  }
  return exit;
}

// Rays the dome meets in a simulation: camera rays off the parabola (the transport and the
// camera map), and rays from points of the sample in all upper directions (the projector grid
// and map). Fixed seed.
std::vector<Ray> DomeRays(const OpticalSystem& optics, int count) {
  std::vector<Ray> rays;
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> u(0, 1);
  const ThinLens& camera = optics.camera();
  while (static_cast<int>(rays.size()) < count / 2) {
    const Ray ray = camera.GenerateRay(u(rng) * camera.params().width,
                                       u(rng) * camera.params().height, u(rng), u(rng));
    bool from_above = false;
    const auto p = optics.parabola().Intersect(ray, 1e-7, &from_above);
    if (!p || !from_above) continue;
    rays.push_back({p->point, Normalize(Reflect(ray.direction, p->normal))});
  }
  while (static_cast<int>(rays.size()) < count) {
    const double radius = 20 * std::sqrt(u(rng)), angle = 2 * M_PI * u(rng);
    const Vec3 w = SphericalDirection(std::acos(std::sqrt(u(rng))), 2 * M_PI * u(rng));
    rays.push_back({{radius * std::cos(angle), radius * std::sin(angle), 0}, w});
  }
  return rays;
}

void ExpectExitsMatchTheReference(const DomeSurface& dome,
                                  const std::vector<DomeProfilePoint>& profile,
                                  const std::vector<Ray>& rays) {
  int hits = 0;
  double worst_t = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const auto hit = dome.Intersect(rays[i], 1e-7);
    const ReferenceExit ref = MarchToExit(profile, rays[i], 1e-7);
    ASSERT_EQ(hit.has_value(), ref.hit) << "ray " << i;
    if (!hit) continue;
    ++hits;
    // The reference's bisection ends at rounding (~1e-13 mm); the exact cone root at 1e-12.
    worst_t = std::max(worst_t, std::abs(hit->t - ref.t));
    const double r = std::hypot(hit->point.x, hit->point.y);
    EXPECT_NEAR(r, ProfileRadius(profile, hit->point.z), 1e-9) << "ray " << i;
  }
  EXPECT_GT(hits, static_cast<int>(rays.size()) / 3);
  EXPECT_LT(worst_t, 1e-9);
}

TEST(OpticsTest, DomeExitIsTheFirstCrossingOfTheProfile) {
  for (const char* name : {"thesis.yaml", "full-dome.yaml"}) {
    SCOPED_TRACE(name);
    const OpticalSystem optics(LoadRig(testing::SourceRig(name)));
    ExpectExitsMatchTheReference(optics.dome(), optics.design().profile, DomeRays(optics, 2000));
  }
}

TEST(OpticsTest, DomeExitOfAProfileThatIsNotConcave) {
  // The thesis profile with a shallow dent (0.02 mm deep, 8 mm tall) in its radius: no longer
  // concave, so the exit is searched by bracketing alone; still the same exits as the reference.
  const OpticalSystem optics(LoadRig(testing::SourceRig("thesis.yaml")));
  DomeDesign dented = optics.design();
  for (DomeProfilePoint& p : dented.profile) {
    const double x = (p.z_mm - 150) / 4;
    if (std::abs(x) < 1) p.r_mm -= 0.02 * (1 + std::cos(M_PI * x)) / 2;
  }
  ExpectExitsMatchTheReference(DomeSurface(dented), dented.profile, DomeRays(optics, 2000));
}

TEST(OpticsTest, ThinLensProjectionInvertsRayGeneration) {
  const Rig rig = LoadRig(testing::SourceRig("thesis.yaml"));
  const double no_tilt[2] = {0.3, -0.2};
  const ThinLens lens(rig.camera, {0.5, -0.3, 1.0}, no_tilt);
  for (double px : {10.25, 680.0, 1300.5}) {
    for (double py : {3.5, 512.0, 1000.75}) {
      for (double u : {-1.0, 0.1, 0.9}) {
        const Ray out = lens.GenerateRay(px, py, u, 0.3);
        // The same ray arriving at the lens from the scene.
        const Ray in{out.At(300), -out.direction};
        const auto proj = lens.Project(in);
        EXPECT_TRUE(proj.in_front);
        EXPECT_TRUE(proj.in_aperture);
        EXPECT_NEAR(proj.px, px, 1e-8);
        EXPECT_NEAR(proj.py, py, 1e-8);
      }
    }
  }
}

TEST(OpticsTest, PathsAreReversible) {
  // A projector ray that lands on the sample, followed back from the landing point along w,
  // returns to the projector pixel it came from.
  const auto& shared = testing::SharedFastThesisRig();
  const OpticalSystem& optics = shared.optics;
  int checked = 0;
  for (int y = 2; y < shared.rig.projector.lens.height; y += 7) {
    for (int x = 3; x < shared.rig.projector.lens.width; x += 7) {
      const auto path = optics.TraceToSample(optics.projector().GenerateRay(x + 0.5, y + 0.5, 0.7, 0.2));
      if (path.status != OpticalSystem::PathStatus::kLanded) continue;
      const auto back = optics.TraceFromSample(path.landing_point, path.w);
      ASSERT_TRUE(back.reached);
      const auto proj = optics.projector().Project(back.at_lens);
      EXPECT_NEAR(proj.px, x + 0.5, 1e-6);
      EXPECT_NEAR(proj.py, y + 0.5, 1e-6);
      ++checked;
    }
  }
  EXPECT_GT(checked, 50);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
