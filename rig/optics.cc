#include "rig/optics.h"

#include <algorithm>
#include <cmath>

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
}

std::optional<Hit> Paraboloid::Intersect(const Ray& ray, double t_min, bool* from_above) const {
  const Vec3 o = pose_.PointToLocal(ray.origin);
  const Vec3 d = pose_.DirectionToLocal(ray.direction);
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
    hit.point = pose_.PointToWorld(p);
    hit.normal = pose_.DirectionToWorld(normal);
    return hit;
  }
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------------
DomeSurface::DomeSurface(const DomeDesign& design) {
  for (const auto& p : design.profile) {
    r_.push_back(p.r_mm);
    z_.push_back(p.z_mm);
    nr_.push_back(p.normal_r);
    nz_.push_back(p.normal_z);
  }
  ZBRDF_ASSERT(z_.size() >= 2, "dome profile too short");
  const int bins = static_cast<int>(4 * z_.size());
  bin_scale_ = bins / (z_.back() - z_.front());
  bin_first_segment_.resize(bins + 1);
  int segment = 0;
  const int last_segment = static_cast<int>(z_.size()) - 2;
  for (int b = 0; b <= bins; ++b) {
    const double z = z_.front() + b / bin_scale_;
    while (segment < last_segment && z_[segment + 1] < z) ++segment;
    bin_first_segment_[b] = segment;
  }
}

double DomeSurface::RadiusAt(double z, int* segment) const {
  const int last_segment = static_cast<int>(z_.size()) - 2;
  int bin = static_cast<int>((z - z_.front()) * bin_scale_);
  bin = std::clamp(bin, 0, static_cast<int>(bin_first_segment_.size()) - 1);
  int s = bin_first_segment_[bin];
  while (s < last_segment && z_[s + 1] < z) ++s;
  *segment = s;
  const double u = (z - z_[s]) / (z_[s + 1] - z_[s]);
  return r_[s] + u * (r_[s + 1] - r_[s]);
}

std::optional<Hit> DomeSurface::Intersect(const Ray& ray, double t_min) const {
  const Vec3& o = ray.origin;
  const Vec3& d = ray.direction;
  const double z_lo = z_.front(), z_hi = z_.back();
  // The t interval within the dome's height range.
  double t_lo = t_min, t_hi;
  if (std::abs(d.z) < 1e-15) {
    if (o.z < z_lo || o.z > z_hi) return std::nullopt;
    t_hi = t_min + 4 * (r_.front() + std::hypot(o.x, o.y)) + 1;
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
  double t_hit = 0.5 * (a + b);
  bool solved = false;
  for (int s : {seg_lo, seg_hi}) {
    const double slope = (r_[s + 1] - r_[s]) / (z_[s + 1] - z_[s]);
    const double c0 = r_[s] + slope * (o.z - z_[s]);
    const double qa = d.x * d.x + d.y * d.y - slope * slope * d.z * d.z;
    const double qb = 2 * (o.x * d.x + o.y * d.y - slope * d.z * c0);
    const double qc = o.x * o.x + o.y * o.y - c0 * c0;
    double roots[2];
    const int n = SolveQuadratic(qa, qb, qc, roots);
    const double tolerance = 1e-9 * (1 + b);
    for (int i = 0; i < n && !solved; ++i) {
      const double t = roots[i];
      if (t < a - tolerance || t > b + tolerance) continue;
      const double z = o.z + t * d.z;
      if (z < z_[s] - 1e-9 || z > z_[s + 1] + 1e-9) continue;
      if (c0 + slope * d.z * t < 0) continue;  // the mirrored nappe of the cone
      t_hit = t;
      solved = true;
    }
    if (solved) break;
  }
  Hit hit;
  hit.t = t_hit;
  hit.point = ray.At(t_hit);
  int s = 0;
  RadiusAt(std::clamp(hit.point.z, z_lo, z_hi), &s);
  const double u = std::clamp((hit.point.z - z_[s]) / (z_[s + 1] - z_[s]), 0.0, 1.0);
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
