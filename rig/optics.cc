#include "rig/optics.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "basis/error.h"
#include "basis/zone.h"

namespace zbrdf {

namespace {

Vec3 RotateX(const Vec3& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {v.x, c * v.y - s * v.z, s * v.y + c * v.z};
}
Vec3 RotateY(const Vec3& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x + s * v.z, v.y, -s * v.x + c * v.z};
}

// Shirley & Chiu concentric map of [0,1)^2 to the unit disk (area-preserving, low distortion).
void ConcentricDisk(double u0, double u1, double* x, double* y) {
  const double a = 2 * u0 - 1, b = 2 * u1 - 1;
  if (a == 0 && b == 0) {
    *x = *y = 0;
    return;
  }
  double r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = (M_PI / 4) * (b / a);
  } else {
    r = b;
    phi = (M_PI / 2) - (M_PI / 4) * (a / b);
  }
  *x = r * std::cos(phi);
  *y = r * std::sin(phi);
}

// Roots of a t^2 + b t + c = 0 in ascending order (stable formulas); returns the count.
int SolveQuadratic(double a, double b, double c, double roots[2]) {
  if (std::abs(a) < 1e-14 * (std::abs(b) + std::abs(c)) || a == 0) {
    if (b == 0) return 0;
    roots[0] = -c / b;
    return 1;
  }
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return 0;
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  double t0 = q / a, t1 = q != 0 ? c / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  roots[0] = t0;
  roots[1] = t1;
  return 2;
}

}  // namespace

Pose TiltedPose(const Vec3& x_axis, const Vec3& y_axis, const Vec3& z_axis, const Vec3& position,
                double tilt_x_deg, double tilt_y_deg) {
  const double ax = DegToRad(tilt_x_deg), ay = DegToRad(tilt_y_deg);
  Pose pose;
  pose.x_axis = RotateY(RotateX(x_axis, ax), ay);
  pose.y_axis = RotateY(RotateX(y_axis, ax), ay);
  pose.z_axis = RotateY(RotateX(z_axis, ax), ay);
  pose.translation = position;
  return pose;
}

// ---------------------------------------------------------------------------------------------
Paraboloid::Paraboloid(const ParabolaParams& params, const Misalignment& misalignment)
    : focal_mm_(params.focal_length_mm), rim_radius_mm_(params.rim_radius_mm) {
  pose_ = TiltedPose({1, 0, 0}, {0, 1, 0}, {0, 0, 1},
                     Vec3{0, 0, params.vertex_height_mm} + misalignment.parabola_offset_mm,
                     misalignment.parabola_tilt_deg[0], misalignment.parabola_tilt_deg[1]);
  untilted_ = pose_.x_axis == Vec3{1, 0, 0} && pose_.y_axis == Vec3{0, 1, 0} &&
              pose_.z_axis == Vec3{0, 0, 1};
}

std::optional<Hit> Paraboloid::Intersect(const Ray& ray, double t_min, bool* from_above) const {
  // Untilted (the design, or a misalignment that only shifts it), the local frame is the
  // world's moved: the rotations' products by 1 and 0 left out give the same values (every
  // camera and projector ray crosses the parabola twice).
  const Vec3 o = untilted_ ? ray.origin - pose_.translation : pose_.PointToLocal(ray.origin);
  const Vec3 d = untilted_ ? ray.direction : pose_.DirectionToLocal(ray.direction);
  // x^2 + y^2 + 4 f z = 0 along o + t d.
  const double a = d.x * d.x + d.y * d.y;
  const double b = 2 * (o.x * d.x + o.y * d.y) + 4 * focal_mm_ * d.z;
  const double c = o.x * o.x + o.y * o.y + 4 * focal_mm_ * o.z;
  double roots[2];
  const int n = SolveQuadratic(a, b, c, roots);
  for (int i = 0; i < n; ++i) {
    const double t = roots[i];
    if (t <= t_min) continue;
    const Vec3 p = o + d * t;
    if (p.x * p.x + p.y * p.y > rim_radius_mm_ * rim_radius_mm_) continue;
    Vec3 normal = Normalize(Vec3{p.x, p.y, 2 * focal_mm_});  // gradient / 2: convex side up
    const bool above = Dot(d, normal) < 0;
    if (from_above) *from_above = above;
    if (!above) normal = -normal;
    Hit hit;
    hit.t = t;
    hit.point = untilted_ ? p + pose_.translation : pose_.PointToWorld(p);
    hit.normal = untilted_ ? normal : pose_.DirectionToWorld(normal);
    return hit;
  }
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------------
DomeSurface::DomeSurface(const DomeDesign& design) {
  for (const auto& p : design.profile) {
    node_.push_back({p.z_mm, p.r_mm, 0.0});
    nr_.push_back(p.normal_r);
    nz_.push_back(p.normal_z);
  }
  ZBRDF_ASSERT(node_.size() >= 2, "dome profile too short");
  for (size_t s = 0; s + 1 < node_.size(); ++s) {
    node_[s].slope = (node_[s + 1].r - node_[s].r) / (node_[s + 1].z - node_[s].z);
  }
  node_.back().slope = node_[node_.size() - 2].slope;
  concave_ = true;
  for (size_t s = 1; s + 1 < node_.size(); ++s) concave_ &= node_[s].slope <= node_[s - 1].slope;
  // The quadric fit, on u in [-1, 1]: least squares of r^2 on 1, u, u^2.
  fit_z0_ = 0.5 * (node_.front().z + node_.back().z);
  fit_u_per_mm_ = 2 / std::max(1e-9, node_.back().z - node_.front().z);
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const Node& n : node_) {
    const double u = (n.z - fit_z0_) * fit_u_per_mm_;
    const Eigen::Vector3d basis(1, u, u * u);
    normal += basis * basis.transpose();
    rhs += n.r * n.r * basis;
  }
  const Eigen::Vector3d fit = normal.ldlt().solve(rhs);
  for (int k = 0; k < 3; ++k) fit_[k] = fit(k);
  // A profile of fewer than three distinct heights has no quadric: the bracketing search only.
  if (!(std::isfinite(fit_[0]) && std::isfinite(fit_[1]) && std::isfinite(fit_[2]))) {
    concave_ = false;
  }
  const double z_lo = node_.front().z, z_hi = node_.back().z;
  const int bins = static_cast<int>(4 * node_.size());
  bin_scale_ = bins / (z_hi - z_lo);
  bin_first_segment_.resize(bins + 1);
  int segment = 0;
  const int last_segment = static_cast<int>(node_.size()) - 2;
  for (int b = 0; b <= bins; ++b) {
    const double z = z_lo + b / bin_scale_;
    while (segment < last_segment && node_[segment + 1].z < z) ++segment;
    bin_first_segment_[b] = segment;
  }
}

double DomeSurface::RadiusAt(double z, int* segment) const {
  const int s = SegmentAt(z);
  *segment = s;
  // The segment's slope rather than a division by its height (RadiusAt runs ~9 times per ray).
  return node_[s].r + (z - node_[s].z) * node_[s].slope;
}

int DomeSurface::SegmentAt(double z) const {
  const int last_segment = static_cast<int>(node_.size()) - 2;
  int bin = static_cast<int>((z - node_.front().z) * bin_scale_);
  bin = std::clamp(bin, 0, static_cast<int>(bin_first_segment_.size()) - 1);
  int s = bin_first_segment_[bin];
  while (s < last_segment && node_[s + 1].z < z) ++s;
  return s;
}

bool DomeSurface::InSegment(int s, double z) const {
  return z >= node_[s].z - 1e-9 && z <= node_[s + 1].z + 1e-9;
}

DomeSurface::Cone DomeSurface::ConeOf(const Vec3& o, const Vec3& d, int s) const {
  Cone cone;
  cone.slope = node_[s].slope;
  cone.c0 = node_[s].r + cone.slope * (o.z - node_[s].z);
  cone.qa = d.x * d.x + d.y * d.y - cone.slope * cone.slope * d.z * d.z;
  cone.qb = 2 * (o.x * d.x + o.y * d.y - cone.slope * d.z * cone.c0);
  const double qc = o.x * o.x + o.y * o.y - cone.c0 * cone.c0;
  cone.n = SolveQuadratic(cone.qa, cone.qb, qc, cone.roots);
  return cone;
}

bool DomeSurface::ConeExit(const Vec3& o, const Vec3& d, int s, double* t_exit) const {
  // ConeOf is the bracketing search's final solve too, so that both give the same root.
  const Cone cone = ConeOf(o, d, s);
  for (int i = 0; i < cone.n; ++i) {
    const double t = cone.roots[i];
    if (2 * cone.qa * t + cone.qb <= 0) continue;  // an entry into the cone, not the exit
    if (!cone.UpperNappe(t, d.z)) continue;
    *t_exit = t;
    return true;
  }
  return false;
}

bool DomeSurface::ExitByCones(const Vec3& o, const Vec3& d, double t_lo, double t_hi,
                              double* t_exit) const {
  // The quadric's exit: (o + t d)_xy^2 = fit(u0 + t du), where it goes from inside to outside.
  const double u0 = (o.z - fit_z0_) * fit_u_per_mm_, du = d.z * fit_u_per_mm_;
  const double qa = d.x * d.x + d.y * d.y - fit_[2] * du * du;
  const double qb = 2 * (o.x * d.x + o.y * d.y) - fit_[1] * du - 2 * fit_[2] * u0 * du;
  const double qc = o.x * o.x + o.y * o.y - (fit_[0] + fit_[1] * u0 + fit_[2] * u0 * u0);
  double roots[2];
  const int n = SolveQuadratic(qa, qb, qc, roots);
  double t = -1;
  for (int i = 0; i < n && t < 0; ++i) {
    if (2 * qa * roots[i] + qb > 0) t = roots[i];
  }
  if (t < 0) return false;
  const double z_lo = node_.front().z, z_hi = node_.back().z;
  t = std::clamp(t, t_lo, t_hi);
  int s = SegmentAt(std::clamp(o.z + t * d.z, z_lo, z_hi));
  // Each cone step is Newton's on the exact local surface: from the quadric's ~0.01 mm the
  // first lands within a segment or two of the exit, the second on it.
  const double tolerance = 1e-9 * (1 + t_hi);
  for (int iter = 0; iter < 8; ++iter) {
    double t_cone = 0;
    if (!ConeExit(o, d, s, &t_cone)) return false;
    if (t_cone < t_lo - tolerance || t_cone > t_hi + tolerance) return false;
    const double z = o.z + t_cone * d.z;
    if (InSegment(s, z)) {
      *t_exit = t_cone;
      return true;
    }
    const int next = SegmentAt(std::clamp(z, z_lo, z_hi));
    if (next == s) return false;
    s = next;
  }
  return false;
}

std::optional<Hit> DomeSurface::Intersect(const Ray& ray, double t_min) const {
  const Vec3& o = ray.origin;
  const Vec3& d = ray.direction;
  const double z_lo = node_.front().z, z_hi = node_.back().z;
  // The t interval within the dome's height range.
  double t_lo = t_min, t_hi;
  if (std::abs(d.z) < 1e-15) {
    if (o.z < z_lo || o.z > z_hi) return std::nullopt;
    t_hi = t_min + 4 * (node_.front().r + std::hypot(o.x, o.y)) + 1;
  } else {
    const double ta = (z_lo - o.z) / d.z, tb = (z_hi - o.z) / d.z;
    t_lo = std::max(t_min, std::min(ta, tb));
    t_hi = std::max(ta, tb);
  }
  if (t_lo >= t_hi) return std::nullopt;
  auto g = [&](double t, int* seg) {
    const Vec3 p = ray.At(t);
    const double z = std::clamp(p.z, z_lo, z_hi);
    // sqrt of the sum of squares rather than std::hypot (several times slower; this runs
    // for every bisection step of every traced ray): millimetre coordinates cannot overflow.
    return std::sqrt(p.x * p.x + p.y * p.y) - RadiusAt(z, seg);
  };
  int seg_lo = 0, seg_hi = 0;
  double g_lo = g(t_lo, &seg_lo);
  double g_hi = g(t_hi, &seg_hi);
  if (g_lo > 0) return std::nullopt;  // starts outside the mirror
  if (g_hi < 0) return std::nullopt;  // leaves through the top hole or below the lower edge
  double t_hit = 0;
  // A concave profile has one exit: found from the quadric guess in two or three cone solves
  // (BM_DomeIntersect: 2x faster than the bracketing below, which stays for other profiles and
  // for rays the guess does not settle).
  if (concave_ && ExitByCones(o, d, t_lo, t_hi, &t_hit)) return HitAt(ray, t_hit);
  // Bracket the exit until it lies within one cone frustum, then solve exactly. The bracket
  // shrinks by false position with the Illinois modification (an end kept twice in a row has
  // its g halved, so both ends close in): g is smooth on the scale of the bracket (thousands
  // of frustums), where bisection took ~14 steps to reach one frustum of the thesis dome's
  // 20000, this takes ~5. Any step that would not fall strictly inside bisects instead.
  double a = t_lo, b = t_hi;
  int kept = 0;  // -1: a was kept last step, +1: b was
  for (int iter = 0; iter < 200 && seg_lo != seg_hi && b - a > 1e-12; ++iter) {
    double mid = (a * g_hi - b * g_lo) / (g_hi - g_lo);
    if (!(mid > a && mid < b)) mid = 0.5 * (a + b);
    int seg_mid = 0;
    const double g_mid = g(mid, &seg_mid);
    if (g_mid < 0) {
      a = mid;
      seg_lo = seg_mid;
      g_lo = g_mid;
      if (kept == +1) g_hi *= 0.5;
      kept = +1;
    } else {
      b = mid;
      seg_hi = seg_mid;
      g_hi = g_mid;
      if (kept == -1) g_lo *= 0.5;
      kept = -1;
    }
  }
  t_hit = 0.5 * (a + b);
  bool solved = false;
  for (int s : {seg_lo, seg_hi}) {
    const Cone cone = ConeOf(o, d, s);
    const double tolerance = 1e-9 * (1 + b);
    for (int i = 0; i < cone.n && !solved; ++i) {
      const double t = cone.roots[i];
      if (t < a - tolerance || t > b + tolerance) continue;
      const double z = o.z + t * d.z;
      if (!InSegment(s, z)) continue;
      if (!cone.UpperNappe(t, d.z)) continue;
      t_hit = t;
      solved = true;
    }
    if (solved) break;
  }
  return HitAt(ray, t_hit);
}

Hit DomeSurface::HitAt(const Ray& ray, double t_hit) const {
  Hit hit;
  hit.t = t_hit;
  hit.point = ray.At(t_hit);
  const int s = SegmentAt(std::clamp(hit.point.z, node_.front().z, node_.back().z));
  const double u = std::clamp((hit.point.z - node_[s].z) / (node_[s + 1].z - node_[s].z), 0.0, 1.0);
  double nr = (1 - u) * nr_[s] + u * nr_[s + 1], nz = (1 - u) * nz_[s] + u * nz_[s + 1];
  const double len = std::sqrt(nr * nr + nz * nz);
  nr /= len;
  nz /= len;
  const double rho = std::sqrt(hit.point.x * hit.point.x + hit.point.y * hit.point.y);
  const double cos_phi = rho > 0 ? hit.point.x / rho : 1.0, sin_phi = rho > 0 ? hit.point.y / rho : 0.0;
  hit.normal = {nr * cos_phi, nr * sin_phi, nz};
  return hit;
}

// ---------------------------------------------------------------------------------------------
ThinLens::ThinLens(const ThinLensParams& params, const Vec3& offset_mm,
                   const double extra_tilt_deg[2])
    : params_(params) {
  pose_ = TiltedPose({1, 0, 0}, {0, -1, 0}, {0, 0, -1}, params.position_mm + offset_mm,
                     params.tilt_deg[0] + extra_tilt_deg[0], params.tilt_deg[1] + extra_tilt_deg[1]);
  image_distance_mm_ = 1.0 / (1.0 / params.focal_length_mm - 1.0 / params.focus_distance_mm);
  aperture_radius_mm_ = params.focal_length_mm / (2 * params.f_number);
  pitch_mm_ = params.pixel_pitch_um * 1e-3;
}

Ray ThinLens::GenerateRay(double px, double py, double u0, double u1) const {
  const double scale = pitch_mm_ * params_.focus_distance_mm / image_distance_mm_;
  const Vec3 focus_point{(px - 0.5 * params_.width) * scale, (py - 0.5 * params_.height) * scale,
                         params_.focus_distance_mm};
  Vec3 aperture{0, 0, 0};
  if (u0 >= 0) {
    double ax, ay;
    ConcentricDisk(u0, u1, &ax, &ay);
    aperture = {ax * aperture_radius_mm_, ay * aperture_radius_mm_, 0};
  }
  Ray ray;
  ray.origin = pose_.PointToWorld(aperture);
  ray.direction = pose_.DirectionToWorld(Normalize(focus_point - aperture));
  return ray;
}

ThinLens::Projection ThinLens::Project(const Ray& incoming) const {
  Projection p;
  const Vec3 o = pose_.PointToLocal(incoming.origin);
  const Vec3 d = pose_.DirectionToLocal(incoming.direction);
  p.in_front = d.z < 0 && o.z > 0;
  if (!p.in_front) return p;
  const double t_lens = -o.z / d.z;
  const Vec3 a = o + d * t_lens;
  p.in_aperture = a.x * a.x + a.y * a.y <= aperture_radius_mm_ * aperture_radius_mm_;
  const double t_focus = (params_.focus_distance_mm - o.z) / d.z;
  const Vec3 q = o + d * t_focus;
  const double to_pixels = image_distance_mm_ / (params_.focus_distance_mm * pitch_mm_);
  p.px = 0.5 * params_.width + q.x * to_pixels;
  p.py = 0.5 * params_.height + q.y * to_pixels;
  return p;
}

double ThinLens::PixelEtendue(double px, double py) const {
  const double xs = (px - 0.5 * params_.width) * pitch_mm_;
  const double ys = (py - 0.5 * params_.height) * pitch_mm_;
  const double cos_field =
      image_distance_mm_ / std::sqrt(image_distance_mm_ * image_distance_mm_ + xs * xs + ys * ys);
  const double cos2 = cos_field * cos_field;
  return pitch_mm_ * pitch_mm_ * 1e-6 * M_PI / (4 * params_.f_number * params_.f_number) * cos2 *
         cos2;
}

// ---------------------------------------------------------------------------------------------
OpticalSystem::OpticalSystem(const Rig& rig, std::shared_ptr<const DomeDesign> design,
                             std::shared_ptr<const DomeSurface> dome)
    : rig_(rig),
      design_(std::move(design)),
      parabola_(rig.parabola, rig.misalignment),
      dome_(std::move(dome)),
      camera_(rig.camera, rig.misalignment.camera_offset_mm, rig.misalignment.camera_tilt_deg),
      projector_(rig.projector.lens, rig.misalignment.projector_offset_mm,
                 rig.misalignment.projector_tilt_deg) {}

OpticalSystem::OpticalSystem(const Rig& rig)
    : OpticalSystem(rig, std::make_shared<const DomeDesign>(DesignDome(rig)), nullptr) {
  dome_ = std::make_shared<const DomeSurface>(*design_);
}

OpticalSystem OpticalSystem::WithMisalignment(const Misalignment& misalignment) const {
  Rig rig = rig_;
  rig.misalignment = misalignment;
  return OpticalSystem(rig, design_, dome_);
}

OpticalSystem::SamplePath OpticalSystem::TraceToSample(const Ray& ray,
                                                      std::vector<Vec3>* vertices) const {
  SamplePath path;
  constexpr double kEps = 1e-7;
  if (vertices) vertices->push_back(ray.origin);
  bool from_above = false;
  const auto p_hit = parabola_.Intersect(ray, kEps, &from_above);
  if (!p_hit || !from_above) {
    path.status = PathStatus::kMissedParabola;
    return path;
  }
  if (vertices) vertices->push_back(p_hit->point);
  const Ray r1{p_hit->point, Normalize(Reflect(ray.direction, p_hit->normal))};
  const auto d_hit = dome_->Intersect(r1, kEps);
  if (!d_hit) {
    path.status = PathStatus::kMissedDome;
    return path;
  }
  if (vertices) vertices->push_back(d_hit->point);
  const Ray r2{d_hit->point, Normalize(Reflect(r1.direction, d_hit->normal))};
  if (r2.direction.z >= 0) {
    path.status = PathStatus::kMissedDome;
    return path;
  }
  const double t_plane = -r2.origin.z / r2.direction.z;
  bool unused = false;
  const auto block = parabola_.Intersect(r2, kEps, &unused);
  if (block && block->t < t_plane) {
    path.status = PathStatus::kBlocked;
    return path;
  }
  path.landing_point = r2.At(t_plane);
  path.landing_point.z = 0;
  if (vertices) vertices->push_back(path.landing_point);
  path.w = -r2.direction;
  const double radius = 0.5 * rig_.sample_diameter_mm;
  path.status = path.landing_point.x * path.landing_point.x +
                            path.landing_point.y * path.landing_point.y <=
                        radius * radius
                    ? PathStatus::kLanded
                    : PathStatus::kOffSample;
  return path;
}

OpticalSystem::LensPath OpticalSystem::TraceFromSample(const Vec3& point, const Vec3& w) const {
  LensPath path;
  constexpr double kEps = 1e-7;
  if (w.z <= 0) return path;
  const Ray r0{point, w};
  bool from_above = false;
  if (parabola_.Intersect(r0, kEps, &from_above)) return path;  // the parabola's underside
  const auto d_hit = dome_->Intersect(r0, kEps);
  if (!d_hit) return path;
  const Ray r1{d_hit->point, Normalize(Reflect(r0.direction, d_hit->normal))};
  const auto p_hit = parabola_.Intersect(r1, kEps, &from_above);
  if (!p_hit || !from_above) return path;
  path.at_lens = Ray{p_hit->point, Normalize(Reflect(r1.direction, p_hit->normal))};
  path.reached = true;
  return path;
}

}  // namespace zbrdf
