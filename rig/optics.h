// Ray optics of the rig: the convex paraboloid, the dome (a surface of revolution from the
// designed profile), thin-lens camera and projector, and the traced light paths.
//
// Intersections are analytic: a quadratic for the paraboloid, and for the dome a quadratic per
// cone frustum between consecutive profile points, found by bracketing. Dome normals are the
// designed normals, interpolated along the profile, so a reflection obeys the law of
// reflection about them exactly; the geometric surface and these normals differ by a fraction
// of the Euler step. All positions in mm, in the sample frame (docs/design.md section 2).
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "basis/vec3.h"
#include "rig/dome_design.h"
#include "rig/rig.h"

namespace zbrdf {

struct Ray {
  Vec3 origin;
  Vec3 direction;  // unit length
  Vec3 At(double t) const { return origin + direction * t; }
};

struct Hit {
  double t = 0;
  Vec3 point;
  Vec3 normal;  // unit; for mirrors, on the reflecting side
};

// Rigid transform local -> world: world = rotation * local + translation. Rotation columns are
// the local axes in world coordinates.
struct Pose {
  Vec3 x_axis{1, 0, 0}, y_axis{0, 1, 0}, z_axis{0, 0, 1};
  Vec3 translation;

  Vec3 PointToWorld(const Vec3& p) const {
    return x_axis * p.x + y_axis * p.y + z_axis * p.z + translation;
  }
  Vec3 DirectionToWorld(const Vec3& d) const { return x_axis * d.x + y_axis * d.y + z_axis * d.z; }
  Vec3 PointToLocal(const Vec3& p) const { return DirectionToLocal(p - translation); }
  Vec3 DirectionToLocal(const Vec3& d) const {
    return {Dot(d, x_axis), Dot(d, y_axis), Dot(d, z_axis)};
  }
};

// Pose with the given local axes rotated by tilt_x about the world x axis, then tilt_y about
// the world y axis (degrees), and the local origin at `position`.
Pose TiltedPose(const Vec3& x_axis, const Vec3& y_axis, const Vec3& z_axis, const Vec3& position,
                double tilt_x_deg, double tilt_y_deg);

// The convex parabolic mirror z_local = -r^2 / (4 f), r <= rim, vertex at the local origin,
// reflecting on its upper (convex) side, black underneath.
class Paraboloid {
 public:
  Paraboloid(const ParabolaParams& params, const Misalignment& misalignment);
  // First intersection with t > t_min; the normal returned faces the side the ray came from,
  // and `from_above` says whether that is the mirror side.
  std::optional<Hit> Intersect(const Ray& ray, double t_min, bool* from_above) const;
  const Pose& pose() const { return pose_; }

 private:
  double focal_mm_, rim_radius_mm_;
  Pose pose_;
  bool untilted_ = false;  // the pose's axes are exactly the world's
};

// The dome: a concave surface of revolution about the z axis, reflecting on its inner side.
class DomeSurface {
 public:
  explicit DomeSurface(const DomeDesign& design);
  // Exit of a ray starting inside the dome (between the axis and the mirror): the hit with
  // the mirror, or nothing if the ray leaves through the top hole or below the lower edge.
  std::optional<Hit> Intersect(const Ray& ray, double t_min) const;
  double z_min() const { return node_.front().z; }
  double z_max() const { return node_.back().z; }

 private:
  // A profile point with the slope dr/dz of the segment above it: a segment's radius, its cone
  // and the walk to the next point read one 24-byte record (the profile is ~500 kB, read at
  // random by every traced ray).
  struct Node {
    double z, r, slope;
  };
  // Profile radius at height z (linear between profile points) and the segment index.
  double RadiusAt(double z, int* segment) const;
  int SegmentAt(double z) const;
  // Whether height z lies on segment s (to 1e-9 mm either side).
  bool InSegment(int s, double z) const;
  // The hit at t on the ray, with the profile's interpolated normal there.
  Hit HitAt(const Ray& ray, double t_hit) const;
  // The exit found from the profile's quadric fit, refined on the segments' cones; false (and
  // the bracketing search decides) where that does not settle on one segment.
  bool ExitByCones(const Vec3& o, const Vec3& d, double t_lo, double t_hi, double* t_exit) const;
  // The ray o + t d against the cone of segment s (its frustum extended): radius c0 + slope t
  // d.z along the ray, and the n roots (ascending) of rho^2 - radius^2 = qa t^2 + qb t + qc.
  struct Cone {
    double slope, c0, qa, qb;
    double roots[2];
    int n;
    // Whether t is on the cone's nappe of positive radius (not its mirror image).
    bool UpperNappe(double t, double d_z) const { return c0 + slope * d_z * t >= 0; }
  };
  Cone ConeOf(const Vec3& o, const Vec3& d, int s) const;
  // The exit of the ray from the cone of segment s: the root where rho^2 - radius^2 goes from
  // negative to positive, on the upper nappe.
  bool ConeExit(const Vec3& o, const Vec3& d, int s, double* t_exit) const;
  std::vector<Node> node_;
  // Whether the profile's radius is concave in z (slopes never rising): then rho - radius is
  // convex along any ray and its exit root unique, so the first cone root found inside its own
  // segment is the exit. Both bundled rigs' profiles are.
  bool concave_ = false;
  // radius^2 ~ fit_[0] + fit_[1] u + fit_[2] u^2, u = (z - fit_z0_) * fit_u_per_mm_ (least
  // squares over the profile points): the first guess of the exit.
  double fit_[3] = {0, 0, 0};
  double fit_z0_ = 0, fit_u_per_mm_ = 1;
  std::vector<double> nr_, nz_;
  std::vector<int> bin_first_segment_;  // uniform z bins -> first candidate segment
  double bin_scale_ = 0;
};

// A thin lens with a pixel grid. Device frame: +z along the optical axis toward the scene;
// pixel (px, py) in continuous coordinates (centers at i + 0.5) images the point
// (x, y) = ((px - W/2), (py - H/2)) * pitch * d_o / d_i on the plane in focus at distance d_o.
class ThinLens {
 public:
  // nominal axes: the camera looks down (-z world); its x is world x and its y is world -y.
  ThinLens(const ThinLensParams& params, const Vec3& offset_mm, const double extra_tilt_deg[2]);

  // Ray leaving the lens at aperture point (u0, u1) in [0,1)^2 (mapped to the disk) toward
  // the focus-plane point conjugate to (px, py).
  Ray GenerateRay(double px, double py, double u0, double u1) const;
  Ray ChiefRay(double px, double py) const { return GenerateRay(px, py, -1, -1); }

  struct Projection {
    bool in_aperture = false;
    bool in_front = false;   // the ray reaches the lens from the scene side
    double px = 0, py = 0;   // continuous pixel coordinates of the image of the ray
  };
  // Where a ray travelling toward the lens crosses the lens plane (aperture test) and which
  // pixel it images to.
  Projection Project(const Ray& incoming) const;

  const ThinLensParams& params() const { return params_; }
  const Pose& pose() const { return pose_; }
  double image_distance_mm() const { return image_distance_mm_; }
  double aperture_radius_mm() const { return aperture_radius_mm_; }
  // Camera etendue of a pixel at (px, py): A_pixel * pi / (4 N^2) * cos^4(field angle),
  // in m^2 sr.
  double PixelEtendue(double px, double py) const;

 private:
  ThinLensParams params_;
  Pose pose_;
  double image_distance_mm_, aperture_radius_mm_, pitch_mm_;
};

// The whole rig's optics with its misalignments.
class OpticalSystem {
 public:
  explicit OpticalSystem(const Rig& rig);
  // The same mirrors (the dome design is shared, not recomputed) with other device and mirror
  // misalignments: cheap enough to call inside a fit.
  OpticalSystem WithMisalignment(const Misalignment& misalignment) const;

  enum class PathStatus { kLanded, kMissedParabola, kMissedDome, kBlocked, kOffSample };
  struct SamplePath {
    PathStatus status = PathStatus::kMissedParabola;
    Vec3 landing_point;  // on the sample plane z = 0
    Vec3 w;              // unit direction from the landing point back along the path
  };
  // Follows a ray leaving a device lens (camera or projector) via parabola and dome to the
  // sample plane. If `vertices` is given, the points where the ray starts, reflects and ends
  // are appended to it (for drawings).
  SamplePath TraceToSample(const Ray& ray, std::vector<Vec3>* vertices = nullptr) const;

  struct LensPath {
    bool reached = false;
    Ray at_lens;  // the ray as it travels toward the projector (or camera) lens
  };
  // Follows a ray leaving the sample point along w (upper hemisphere) via dome and parabola
  // toward the devices.
  LensPath TraceFromSample(const Vec3& point, const Vec3& w) const;

  const Rig& rig() const { return rig_; }
  const DomeDesign& design() const { return *design_; }
  const ThinLens& camera() const { return camera_; }
  const ThinLens& projector() const { return projector_; }
  const Paraboloid& parabola() const { return parabola_; }
  const DomeSurface& dome() const { return *dome_; }

 private:
  OpticalSystem(const Rig& rig, std::shared_ptr<const DomeDesign> design,
                std::shared_ptr<const DomeSurface> dome);
  Rig rig_;
  std::shared_ptr<const DomeDesign> design_;
  Paraboloid parabola_;
  std::shared_ptr<const DomeSurface> dome_;
  ThinLens camera_, projector_;
};

}  // namespace zbrdf
