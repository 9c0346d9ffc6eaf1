#include "calibration/geometry.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <ceres/ceres.h>
#include <opencv2/imgproc.hpp>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "basis/zone.h"
#include "drivers/bgr_png.h"
#include "rig/optics.h"

namespace zbrdf {

namespace {

constexpr int kParams = 10;
constexpr double kEdgeSigmaPx = 0.15;
constexpr double kCorrespondenceSigmaPx = 0.29;  // 1 / sqrt(12): a decoded pixel's rounding
constexpr double kOutlierPx = 4.0;

Misalignment FromParams(const double* p, const Misalignment& fixed) {
  Misalignment m = fixed;  // keeps the parabola's
  m.camera_offset_mm = {p[0], p[1], p[2]};
  m.camera_tilt_deg[0] = p[3];
  m.camera_tilt_deg[1] = p[4];
  m.projector_offset_mm = {p[5], p[6], p[7]};
  m.projector_tilt_deg[0] = p[8];
  m.projector_tilt_deg[1] = p[9];
  return m;
}

const char* kParamNames[kParams] = {"camera_offset_x_mm",    "camera_offset_y_mm",
                                    "camera_offset_z_mm",    "camera_tilt_x_deg",
                                    "camera_tilt_y_deg",     "projector_offset_x_mm",
                                    "projector_offset_y_mm", "projector_offset_z_mm",
                                    "projector_tilt_x_deg",  "projector_tilt_y_deg"};

bool ChiefRayLands(const OpticalSystem& optics, double px, double py) {
  return optics.TraceToSample(optics.camera().ChiefRay(px, py)).status ==
         OpticalSystem::PathStatus::kLanded;
}

// The projector pixel a camera pixel sees through a flat mirror at the sample.
bool ModelCorrespondence(const OpticalSystem& optics, double px, double py, double* u, double* v);

// A camera pixel sees projector light through the mirror: its chief ray lands, and mirrored at
// the sample it goes back through the projector's aperture onto the projector's pixels.
bool MirrorPathOk(const OpticalSystem& optics, double px, double py) {
  const OpticalSystem::SamplePath path = optics.TraceToSample(optics.camera().ChiefRay(px, py));
  if (path.status != OpticalSystem::PathStatus::kLanded) return false;
  const OpticalSystem::LensPath back =
      optics.TraceFromSample(path.landing_point, Vec3{-path.w.x, -path.w.y, path.w.z});
  if (!back.reached) return false;
  const ThinLens::Projection p = optics.projector().Project(back.at_lens);
  const ThinLensParams& lens = optics.projector().params();
  return p.in_front && p.in_aperture && p.px >= 0 && p.py >= 0 && p.px < lens.width &&
         p.py < lens.height;
}

enum class EdgeKind { kWhiteTarget, kMirror };

// Radius along the ray from (cx, cy) at `angle` where the pixel starts (inner) or stops (outer)
// seeing light: for the white target, where the chief ray lands on the sample; through the
// mirror, where the mirrored path reaches the projector (MirrorPathOk). Searched near `guess`;
// false if there is no such change within 120 px of it.
bool ModelEdgeRadius(const OpticalSystem& optics, EdgeKind kind, double cx, double cy, double angle,
                     bool outer, double guess, double* radius) {
  const double dx = std::cos(angle), dy = std::sin(angle);
  auto lands = [&](double r) {
    const double px = cx + r * dx, py = cy + r * dy;
    return kind == EdgeKind::kWhiteTarget ? ChiefRayLands(optics, px, py) : MirrorPathOk(optics, px, py);
  };
  // Inside the annulus is "lands"; find lo (the side nearer the centre for inner edges) and
  // hi with lands(lo) != lands(hi), closest to the guess.
  const bool want_lo = outer;  // inner edge: dark inside, lit outside; outer: lit inside
  double lo = -1, hi = -1;
  constexpr double kH = 0.5;
  for (int k = 0; k < 240 && lo < 0; ++k) {  // intervals of kH outward from the guess
    for (const double a : {guess + k * kH, guess - (k + 1) * kH}) {
      const double b = a + kH;
      if (a < 0) continue;
      if (lands(a) == want_lo && lands(b) != want_lo) {
        lo = a;
        hi = b;
        break;
      }
    }
  }
  if (lo < 0) return false;
  for (int i = 0; i < 32; ++i) {  // 0.5 px / 2^32: far below what the derivatives need
    const double mid = 0.5 * (lo + hi);
    if (lands(mid) == want_lo) lo = mid;
    else hi = mid;
  }
  *radius = 0.5 * (lo + hi);
  return true;
}

// The projector pixel a camera pixel sees through a flat mirror at the sample.
bool ModelCorrespondence(const OpticalSystem& optics, double px, double py, double* u, double* v) {
  const OpticalSystem::SamplePath path = optics.TraceToSample(optics.camera().ChiefRay(px, py));
  if (path.status != OpticalSystem::PathStatus::kLanded) return false;
  const Vec3 mirrored{-path.w.x, -path.w.y, path.w.z};
  const OpticalSystem::LensPath back = optics.TraceFromSample(path.landing_point, mirrored);
  if (!back.reached) return false;
  const ThinLens::Projection p = optics.projector().Project(back.at_lens);
  if (!p.in_front) return false;
  *u = p.px;
  *v = p.py;
  return true;
}

struct Observation {
  float px, py, u, v;  // camera pixel centre, decoded projector coordinates
};

struct GeometryResiduals {
  const OpticalSystem* base;
  const AnnulusEdges* edges;         // white target
  const AnnulusEdges* mirror_edges;  // through the mirror
  const std::vector<Observation>* observations;

  bool operator()(double const* const* parameters, double* residuals) const {
    const OpticalSystem optics = base->WithMisalignment(FromParams(parameters[0], base->rig().misalignment));
    std::atomic<bool> ok{true};
    const int n_white = static_cast<int>(edges->points.size());
    const int n_edges = n_white + static_cast<int>(mirror_edges->points.size());
    ParallelFor(n_edges, 8, [&](int64_t i0, int64_t i1) {
      for (int64_t i = i0; i < i1; ++i) {
        const bool white = i < n_white;
        const AnnulusEdges& set = white ? *edges : *mirror_edges;
        const AnnulusEdgePoint& e = set.points[white ? i : i - n_white];
        double r;
        if (!ModelEdgeRadius(optics, white ? EdgeKind::kWhiteTarget : EdgeKind::kMirror, set.center_x,
                             set.center_y, e.angle_rad, e.outer, e.radius_px, &r)) {
          ok = false;
          return;
        }
        residuals[i] = (r - e.radius_px) / kEdgeSigmaPx;
      }
    });
    const int n_obs = static_cast<int>(observations->size());
    ParallelFor(n_obs, 64, [&](int64_t i0, int64_t i1) {
      for (int64_t i = i0; i < i1; ++i) {
        const Observation& o = (*observations)[i];
        double u, v;
        if (!ModelCorrespondence(optics, o.px, o.py, &u, &v)) {
          ok = false;
          return;
        }
        residuals[n_edges + 2 * i] = (u - o.u) / kCorrespondenceSigmaPx;
        residuals[n_edges + 2 * i + 1] = (v - o.v) / kCorrespondenceSigmaPx;
      }
    });
    return ok;
  }
};

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

AnnulusEdges FindAnnulusEdges(const RateImage& image, int rays) {
  const int w = image.width, h = image.height;
  // Normalize each Bayer channel by the median of its lit pixels (the white target is white,
  // but the channels' sensitivities differ on a real camera).
  std::vector<float> normalized(image.rate.size(), 0.0f);
  for (int ch = -1; ch < 3; ++ch) {
    std::vector<float> values;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const size_t i = static_cast<size_t>(y) * w + x;
        if (image.valid[i] && BayerChannel(image.layout, x, y) == ch) values.push_back(image.rate[i]);
      }
    }
    if (values.empty()) continue;
    std::vector<float> sorted = values;
    const size_t q = sorted.size() * 95 / 100;
    std::nth_element(sorted.begin(), sorted.begin() + q, sorted.end());
    const float bright = sorted[q];
    std::vector<double> lit;
    for (float v : values) {
      if (v > 0.2f * bright) lit.push_back(v);
    }
    const double scale = Median(lit);
    if (!(scale > 0)) continue;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const size_t i = static_cast<size_t>(y) * w + x;
        if (image.valid[i] && BayerChannel(image.layout, x, y) == ch) {
          normalized[i] = static_cast<float>(image.rate[i] / scale);
        }
      }
    }
  }
  AnnulusEdges edges;
  double sx = 0, sy = 0;
  long n = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (normalized[static_cast<size_t>(y) * w + x] > 0.35f) {
        sx += x + 0.5;
        sy += y + 0.5;
        ++n;
      }
    }
  }
  if (n < 100) throw DeviceError("the white target's image shows no lit annulus; is it lit and in place?");
  edges.center_x = sx / n;
  edges.center_y = sy / n;
  auto sample = [&](double px, double py) {  // bilinear, pixel centres at i + 0.5
    const double fx = px - 0.5, fy = py - 0.5;
    const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
    const double ax = fx - x0, ay = fy - y0;
    double sum = 0;
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 2; ++i) {
        const int xx = std::clamp(x0 + i, 0, w - 1), yy = std::clamp(y0 + j, 0, h - 1);
        sum += (i ? ax : 1 - ax) * (j ? ay : 1 - ay) * normalized[static_cast<size_t>(yy) * w + xx];
      }
    }
    return sum;
  };
  constexpr double kStep = 0.25;
  for (int k = 0; k < rays; ++k) {
    const double angle = 2 * M_PI * k / rays;
    const double dx = std::cos(angle), dy = std::sin(angle);
    std::vector<double> profile;
    for (double r = 0;; r += kStep) {
      const double px = edges.center_x + r * dx, py = edges.center_y + r * dy;
      if (px < 0.5 || py < 0.5 || px > w - 0.5 || py > h - 0.5) break;
      profile.push_back(sample(px, py));
    }
    // The longest lit run is the annulus.
    int best_a = -1, best_b = -1;
    for (int i = 0; i < static_cast<int>(profile.size());) {
      if (profile[i] <= 0.35) {
        ++i;
        continue;
      }
      int j = i;
      while (j + 1 < static_cast<int>(profile.size()) && profile[j + 1] > 0.35) ++j;
      if (j - i > best_b - best_a) best_a = i, best_b = j;
      i = j + 1;
    }
    if (best_a < 0 || (best_b - best_a) * kStep < 16) continue;
    auto plateau = [&](int from, int to) {
      std::vector<double> v;
      for (int i = std::max(0, from); i <= std::min(to, static_cast<int>(profile.size()) - 1); ++i) {
        v.push_back(profile[i]);
      }
      return Median(v);
    };
    const int near = static_cast<int>(3 / kStep), far = static_cast<int>(9 / kStep);
    // Inner edge: the first upward crossing of half the level just inside the annulus.
    if (best_a > 0) {
      const double half = 0.5 * plateau(best_a + near, best_a + far);
      for (int i = std::max(1, best_a - near); i <= best_a + near; ++i) {
        if (profile[i - 1] < half && profile[i] >= half) {
          const double t = (half - profile[i - 1]) / (profile[i] - profile[i - 1]);
          edges.points.push_back({angle, false, (i - 1 + t) * kStep});
          break;
        }
      }
    }
    // Outer edge: the last downward crossing.
    if (best_b + 1 < static_cast<int>(profile.size())) {
      const double half = 0.5 * plateau(best_b - far, best_b - near);
      for (int i = std::min(static_cast<int>(profile.size()) - 1, best_b + near); i > best_b - near; --i) {
        if (profile[i - 1] >= half && profile[i] < half) {
          const double t = (profile[i - 1] - half) / (profile[i - 1] - profile[i]);
          edges.points.push_back({angle, true, (i - 1 + t) * kStep});
          break;
        }
      }
    }
  }
  if (edges.points.size() < 20) {
    throw DeviceError("found only " + std::to_string(edges.points.size()) +
                      " points on the annulus edges; is the white target lit and in focus?");
  }
  return edges;
}

MapDifference CompareDirectionMaps(const DirectionMap& a, const DirectionMap& b) {
  std::vector<double> angles;
  for (int i = 0; i < std::min(a.size(), b.size()); ++i) {
    if (!a.Valid(i) || !b.Valid(i)) continue;
    const double c = std::clamp(Dot(a.Direction(i), b.Direction(i)), -1.0, 1.0);
    angles.push_back(RadToDeg(std::acos(c)));
  }
  MapDifference d;
  d.pixels = static_cast<int>(angles.size());
  if (angles.empty()) return d;
  std::sort(angles.begin(), angles.end());
  d.median_deg = angles[angles.size() / 2];
  d.p95_deg = angles[angles.size() * 95 / 100];
  d.max_deg = angles.back();
  return d;
}

void GeometryOptions::Validate() const {
  OptionChecker check("GeometryOptions");
  check.InRange("edge_rays", edge_rays, 8, 3600)
      .AtLeast("max_correspondences", max_correspondences, 10)
      .AtLeast("max_iterations", max_iterations, 1)
      .ThrowIfInvalid();
}

GeometryResult FitGeometry(const Rig& design, const AnnulusEdges& edges,
                           const Correspondences& correspondences, const GeometryOptions& options) {
  options.Validate();
  GeometryResult result;
  result.edges = edges;
  result.correspondences = correspondences;
  const OpticalSystem base(design);
  double params[kParams] = {0};
  {
    const Misalignment& m = design.misalignment;  // start from the design's own values
    params[0] = m.camera_offset_mm.x, params[1] = m.camera_offset_mm.y, params[2] = m.camera_offset_mm.z;
    params[3] = m.camera_tilt_deg[0], params[4] = m.camera_tilt_deg[1];
    params[5] = m.projector_offset_mm.x, params[6] = m.projector_offset_mm.y;
    params[7] = m.projector_offset_mm.z;
    params[8] = m.projector_tilt_deg[0], params[9] = m.projector_tilt_deg[1];
  }
  auto current = [&] { return base.WithMisalignment(FromParams(params, design.misalignment)); };
  // Edges the current model reproduces (within 120 px).
  auto usable_edges = [&](const AnnulusEdges& in, EdgeKind kind) {
    const OpticalSystem optics = current();
    AnnulusEdges out = in;
    out.points.clear();
    for (const AnnulusEdgePoint& e : in.points) {
      double r;
      if (ModelEdgeRadius(optics, kind, in.center_x, in.center_y, e.angle_rad, e.outer, e.radius_px, &r)) {
        out.points.push_back(e);
      }
    }
    return out;
  };
  ceres::Solver::Summary summary;
  auto solve = [&](const AnnulusEdges& white, const AnnulusEdges& mirror,
                   const std::vector<Observation>& obs, const std::vector<int>& held,
                   double* covariance_out, bool* covariance_ok) {
    ceres::Problem problem;
    ceres::NumericDiffOptions numeric;
    numeric.relative_step_size = 1e-4;
    auto* cost = new ceres::DynamicNumericDiffCostFunction<GeometryResiduals, ceres::CENTRAL>(
        new GeometryResiduals{&base, &white, &mirror, &obs}, ceres::TAKE_OWNERSHIP, numeric);
    cost->AddParameterBlock(kParams);
    cost->SetNumResiduals(static_cast<int>(white.points.size() + mirror.points.size() + 2 * obs.size()));
    problem.AddResidualBlock(cost, nullptr, params);
    problem.SetManifold(params, new ceres::SubsetManifold(kParams, held));
    for (int i = 0; i < kParams; ++i) {
      if (std::find(held.begin(), held.end(), i) != held.end()) continue;
      const bool tilt = i == 3 || i == 4 || i == 8 || i == 9;
      problem.SetParameterLowerBound(params, i, tilt ? -5 : -10);
      problem.SetParameterUpperBound(params, i, tilt ? 5 : 10);
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = options.max_iterations;
    so.function_tolerance = 1e-12;
    so.parameter_tolerance = 1e-12;
    so.gradient_tolerance = 1e-14;
    so.logging_type = ceres::SILENT;
    ceres::Solve(so, &problem, &summary);
    if (!summary.IsSolutionUsable()) {
      throw NumericalError("geometry fit failed: " + summary.BriefReport());
    }
    if (covariance_out) {
      ceres::Covariance::Options co;
      co.algorithm_type = ceres::DENSE_SVD;
      ceres::Covariance covariance(co);
      const std::vector<std::pair<const double*, const double*>> blocks = {{params, params}};
      *covariance_ok = covariance.Compute(blocks, &problem) &&
                       covariance.GetCovarianceBlock(params, params, covariance_out);
    }
  };

  // Stage 1: the camera alone, from the white target's annulus edges (a misaligned camera's
  // directions can be off by degrees, too far for the correspondences to start from).
  const AnnulusEdges white = usable_edges(edges, EdgeKind::kWhiteTarget);
  if (white.points.size() < 20) {
    throw DeviceError("geometry: the annulus edges are too far from what the design rig predicts "
                      "(only " + std::to_string(white.points.size()) + " usable); check the rig file");
  }
  const AnnulusEdges none;
  solve(white, none, {}, {5, 6, 7, 8, 9}, nullptr, nullptr);

  // Stage 2: everything observable, from the correspondences that the camera-fitted model
  // traces (neighbourhood included: the fit's small steps must never push a path off a rim)
  // and the edges of the light seen through the mirror.
  std::vector<Observation> all;
  for (int y = 0; y < correspondences.camera_height; ++y) {
    for (int x = 0; x < correspondences.camera_width; ++x) {
      const int i = y * correspondences.camera_width + x;
      if (!correspondences.Has(i)) continue;
      all.push_back({static_cast<float>(x + 0.5), static_cast<float>(y + 0.5), correspondences.u[i],
                     correspondences.v[i]});
    }
  }
  const size_t stride = std::max<size_t>(1, all.size() / std::max(1, options.max_correspondences));
  std::vector<Observation> observations;
  {
    const OpticalSystem optics = current();
    for (size_t i = 0; i < all.size(); i += stride) {
      bool inside = true;
      for (int dy = -2; dy <= 2 && inside; dy += 2) {
        for (int dx = -2; dx <= 2 && inside; dx += 2) {
          double u, v;
          inside = ModelCorrespondence(optics, all[i].px + dx, all[i].py + dy, &u, &v);
        }
      }
      if (inside) observations.push_back(all[i]);
    }
  }
  if (observations.size() < 50) {
    throw DeviceError("geometry: only " + std::to_string(observations.size()) +
                      " usable correspondences; was the mirror in place?");
  }
  AnnulusEdges mirror;
  if (correspondences.contrast.size() == correspondences.u.size()) {
    RateImage contrast;
    contrast.width = correspondences.camera_width;
    contrast.height = correspondences.camera_height;
    contrast.layout = PixelLayout::kMono;  // through the mirror the light is white
    contrast.rate = correspondences.contrast;
    contrast.valid.assign(contrast.rate.size(), 1);
    mirror = usable_edges(FindAnnulusEdges(contrast, options.edge_rays), EdgeKind::kMirror);
    result.mirror_edges = mirror;
  }
  const std::vector<int> held = {5, 6};  // the projector's lateral offset (geometry.h)
  solve(white, mirror, observations, held, nullptr, nullptr);
  // Stage 3: without the correspondences the model misses by more than kOutlierPx.
  int dropped = 0;
  {
    const OpticalSystem fitted = current();
    std::vector<Observation> kept;
    for (const Observation& o : observations) {
      double u, v;
      if (ModelCorrespondence(fitted, o.px, o.py, &u, &v) && std::hypot(u - o.u, v - o.v) <= kOutlierPx) {
        kept.push_back(o);
      }
    }
    dropped = static_cast<int>(observations.size() - kept.size());
    observations = std::move(kept);
  }
  double covariance[kParams * kParams];
  bool covariance_ok = false;
  solve(white, mirror, observations, held, covariance, &covariance_ok);
  result.misalignment = FromParams(params, design.misalignment);

  // Residuals in pixels at the solution.
  const OpticalSystem fitted = current();
  auto edge_rms = [&](const AnnulusEdges& set, EdgeKind kind) {
    double sum2 = 0;
    for (const AnnulusEdgePoint& e : set.points) {
      double r;
      if (ModelEdgeRadius(fitted, kind, set.center_x, set.center_y, e.angle_rad, e.outer, e.radius_px, &r)) {
        sum2 += (r - e.radius_px) * (r - e.radius_px);
      }
    }
    return set.points.empty() ? 0.0 : std::sqrt(sum2 / set.points.size());
  };
  double corr2 = 0;
  for (const Observation& o : observations) {
    double u, v;
    if (ModelCorrespondence(fitted, o.px, o.py, &u, &v)) corr2 += (u - o.u) * (u - o.u) + (v - o.v) * (v - o.v);
  }
  const int dof = static_cast<int>(white.points.size() + mirror.points.size() + 2 * observations.size()) -
                  (kParams - static_cast<int>(held.size()));
  // Standard errors: the covariance of the weighted problem, scaled by the reduced chi^2.
  const double reduced_chi2 = dof > 0 ? 2 * summary.final_cost / dof : 1;
  nlohmann::json parameters = nlohmann::json::object();
  for (int i = 0; i < kParams; ++i) {
    nlohmann::json p = {{"value", params[i]}};
    if (i == 5 || i == 6) {
      p["held"] = "not observable: folded into the projector tilt (see docs/calibration.md)";
    } else if (covariance_ok) {
      p["standard_error"] = std::sqrt(std::max(0.0, covariance[i * kParams + i] * reduced_chi2));
    }
    parameters[kParamNames[i]] = p;
  }
  result.report = {
      {"parameters", parameters},
      {"covariance", covariance_ok ? "ok" : "rank deficient: some parameters are not determined"},
      {"edge_points", white.points.size()},
      {"edge_rms_px", edge_rms(white, EdgeKind::kWhiteTarget)},
      {"mirror_edge_points", mirror.points.size()},
      {"mirror_edge_rms_px", edge_rms(mirror, EdgeKind::kMirror)},
      {"correspondences", observations.size()},
      {"correspondences_decoded", correspondences.count},
      {"correspondences_dropped", dropped},
      {"correspondence_rms_projector_px",
       observations.empty() ? 0.0 : std::sqrt(corr2 / observations.size())},
      {"iterations", summary.iterations.size()},
      {"termination", summary.message}};
  return result;
}

GeometryResult CalibrateGeometry(CalibrationRig& rig, const Rig& design,
                                 const RigCalibration& nominal, const GeometryOptions& options) {
  options.Validate();  // before anything is captured
  rig.place_target(Target::kWhite);
  const double exposure = MeterWhite(rig, nominal);
  ShowPattern(rig, UniformPattern(nominal, 0));
  const HdrImage dark = TakeHdr(rig, nominal, {exposure, 4 * exposure}, "white target, projector black");
  ShowPattern(rig, UniformPattern(nominal, (1 << nominal.projector_bit_depth) - 1));
  const HdrImage lit = TakeHdr(rig, nominal, {exposure, 4 * exposure}, "white target, full white");
  const AnnulusEdges edges = FindAnnulusEdges(Subtract(lit, dark), options.edge_rays);
  rig.place_target(Target::kMirror);
  const Correspondences correspondences = CaptureGrayCode(rig, nominal);
  Report(rig.progress, {"geometry fit", 0, 1, "fits"});
  GeometryResult result = FitGeometry(design, edges, correspondences, options);
  Report(rig.progress, {"geometry fit", 1, 1, "fits"});
  return result;
}

void WriteGeometryFigure(const std::string& path, const GeometryResult& result, const Rig& design) {
  const int w = design.camera.width, h = design.camera.height;
  const double scale = std::max(1.0, 700.0 / std::max(w, h));
  cv::Mat img(static_cast<int>(h * scale) + 40, static_cast<int>(w * scale), CV_8UC3,
              cv::Scalar(255, 255, 255));
  // Decoded correspondences in grey, observed edges in blue, fitted model edges in red.
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (result.correspondences.Has(y * w + x)) {
        cv::rectangle(img, cv::Point(static_cast<int>(x * scale), static_cast<int>(y * scale) + 40),
                      cv::Point(static_cast<int>((x + 1) * scale) - 1, static_cast<int>((y + 1) * scale) + 39),
                      cv::Scalar(215, 215, 215), cv::FILLED);
      }
    }
  }
  const OpticalSystem fitted = OpticalSystem(design).WithMisalignment(result.misalignment);
  const AnnulusEdges& e = result.edges;
  for (const AnnulusEdgePoint& p : e.points) {
    const double dx = std::cos(p.angle_rad), dy = std::sin(p.angle_rad);
    const cv::Point observed(static_cast<int>((e.center_x + p.radius_px * dx) * scale),
                             static_cast<int>((e.center_y + p.radius_px * dy) * scale) + 40);
    cv::circle(img, observed, 3, cv::Scalar(200, 80, 0), cv::FILLED, cv::LINE_AA);
    double r;
    if (ModelEdgeRadius(fitted, EdgeKind::kWhiteTarget, e.center_x, e.center_y, p.angle_rad, p.outer,
                        p.radius_px, &r)) {
      const cv::Point model(static_cast<int>((e.center_x + r * dx) * scale),
                            static_cast<int>((e.center_y + r * dy) * scale) + 40);
      cv::circle(img, model, 2, cv::Scalar(0, 0, 220), cv::FILLED, cv::LINE_AA);
    }
  }
  char title[200];
  std::snprintf(title, sizeof(title), "geometry: edges observed (blue), fitted (red); edge rms %.3g px",
                result.report.value("edge_rms_px", 0.0));
  cv::putText(img, title, {10, 25}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  WriteFileAtomically(path, EncodeBgrPng(img));
}

}  // namespace zbrdf
