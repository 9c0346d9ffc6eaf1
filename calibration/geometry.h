// Geometric calibration: the misalignment of the camera and the projector against the mirrors
// (offsets in mm and tilts in degrees; the parabola and dome are the reference frame),
// estimated with Ceres from
//   (a) the edges of the mirror annulus in an HDR image of the white target under a full-white
//       pattern: along 90 rays from the annulus centre, the inner and outer positions where the
//       image falls to half its nearby level; the model's edge is where the camera's chief ray
//       stops reaching the sample (bisection along the same ray), and
//   (b) Gray-code correspondences through the mirror target: the camera pixel's chief ray,
//       mirrored at the sample, is traced back to the projector and must image to the decoded
//       projector pixel, and
//   (c) the edges of the annulus of camera pixels that see projector light through the mirror
//       (full white minus black), where the camera's or the projector's view ends.
// Fitted: the camera's offset (3) and tilt (2), the projector's axial offset and tilt (2). The
// projector's lateral offset is held at the design's: the paraboloid's normal is linear in
// position, so shifting the projector sideways turns every direction it lights the sample
// from almost exactly as tilting it does (1 mm acts as 0.21 deg on the thesis rig), and nothing
// seen from the sample tells them apart. The Jacobian of all observations has a singular
// value of 0.14 (in units of the observations' standard errors per mm) along that combination,
// against >= 7.8 for every other: a lateral offset would come out with an uncertainty of
// millimetres while the direction maps, which are all that capture needs, are determined by
// the fitted tilt to a small fraction of a degree.
// Residuals are in pixels, weighted by their expected error (0.15 px for edges, 0.29 px, the
// rounding of a decoded pixel, for correspondences); correspondences off by more than 4 px
// after a first fit are dropped and the fit repeated. The direction maps of the calibrated rig
// are traced afresh (calibration_data.h, ApplyCalibration).
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "calibration/gray_code.h"
#include "calibration/rig_access.h"
#include "rig/direction_maps.h"
#include "rig/rig.h"

namespace zbrdf {

struct GeometryOptions {
  int edge_rays = 90;               // rays from the annulus centre
  int max_correspondences = 1500;   // evenly subsampled
  int max_iterations = 50;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct AnnulusEdgePoint {
  double angle_rad = 0;  // of the ray from the centre (image x right, y down)
  bool outer = false;
  double radius_px = 0;  // from the centre along the ray
};

struct AnnulusEdges {
  double center_x = 0, center_y = 0;  // continuous pixel coordinates
  std::vector<AnnulusEdgePoint> points;
};

// Finds the annulus edges in a (dark-subtracted) image of the lit white target.
AnnulusEdges FindAnnulusEdges(const RateImage& image, int rays);

struct GeometryResult {
  Misalignment misalignment;
  Correspondences correspondences;
  AnnulusEdges edges;         // white target
  AnnulusEdges mirror_edges;  // of the light seen through the mirror
  nlohmann::json report;  // parameters with standard errors, residuals, map change
};

// Places the white target, then the mirror, captures and fits. `nominal` is the design rig's
// calibration (exposure metering, noise model, contrast thresholds).
GeometryResult CalibrateGeometry(CalibrationRig& rig, const Rig& design,
                                 const RigCalibration& nominal, const GeometryOptions& options = {});

// The fit alone, on given observations (the tests' and the CLI's entry point after capture).
GeometryResult FitGeometry(const Rig& design, const AnnulusEdges& edges,
                           const Correspondences& correspondences, const GeometryOptions& options = {});

// Angles between two maps' directions over the pixels valid in both, in degrees.
struct MapDifference {
  double median_deg = 0, p95_deg = 0, max_deg = 0;
  int pixels = 0;
};
MapDifference CompareDirectionMaps(const DirectionMap& a, const DirectionMap& b);

// Residual picture: the annulus edges observed and fitted (PNG).
void WriteGeometryFigure(const std::string& path, const GeometryResult& result, const Rig& design);

}  // namespace zbrdf
