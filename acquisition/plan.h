// A capture plan: which patterns to show, at which exposures, in which order, and how long the
// rig will take.
//
// One pattern per non-empty lobe of each zonal basis function Z_lm, l <= order (the positive
// and the negative part are shown separately and subtracted later; Z_00 has no negative part),
// plus one dark pattern (projector black) that removes the projector's black level and any
// ambient light from the lobes without a negative partner. Each pattern is captured at every
// exposure of the bracket (default as the thesis: 3 exposures 2 f-stops apart) and `repeats`
// times. Frame index i of the plan is fixed once the plan is made; a session's journal and the
// virtual camera's noise are keyed on it.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "basis/zone.h"
#include "rig/rig.h"

namespace zbrdf {

struct PlannedLobe {
  enum class Kind { kDark, kPositive, kNegative };
  Kind kind = Kind::kDark;
  int l = 0, m = 0;  // the basis function (unused for kDark)
  // "dark", "Z3,-1+", "Z3,-1-": used in file names and reports.
  std::string Name() const;
};

struct PlannedFrame {
  int lobe = 0;      // index into CapturePlan::lobes
  int exposure = 0;  // index into CapturePlan::exposures_us
  int repeat = 0;
};

struct CapturePlan {
  double theta_min_rad = 0, theta_max_rad = 0;
  int order = 4;
  std::vector<PlannedLobe> lobes;
  std::vector<double> exposures_us;  // ascending
  int repeats = 1;

  Zone zone() const { return Zone(theta_min_rad, theta_max_rad); }
  int frame_count() const {
    return static_cast<int>(lobes.size() * exposures_us.size()) * repeats;
  }
  // Frames in capture order: lobe by lobe, and within a lobe repeat by repeat, each over the
  // bracket from the shortest exposure.
  PlannedFrame Frame(int index) const;
  int FrameIndex(int lobe, int exposure, int repeat) const;

  nlohmann::json ToJson() const;
  // Throws InputError naming `where` (e.g. "sessions/x/session.json plan") and the field if the
  // JSON is not a valid plan: "sessions/x/session.json plan field 'order' is missing".
  static CapturePlan FromJson(const nlohmann::json& j, const std::string& where = "capture plan");
};

struct PlanOptions {
  double theta_min_rad = 0, theta_max_rad = 0;  // the zone (from the rig's coverage by default)
  int order = 4;
  int exposures = 3;            // bracket size
  double stops_apart = 2;       // f-stops between neighbouring exposures (factor 2^stops)
  double shortest_exposure_us = 10000;
  int repeats = 1;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

// Throws InputError for an order outside [0, 30], exposures outside [1, 10], stops <= 0, etc.
CapturePlan MakePlan(const PlanOptions& options);

// The wall time the rig needs for the plan (the virtual rig charges the same): per pattern the
// projector settle time, per frame max(frame period, exposure + readout).
double PredictCaptureTimeS(const CapturePlan& plan, const TimingParams& timing);

// The default zone for a rig: its covered theta range, shrunk by `margin_deg` on each side and
// rounded inward to 0.1 deg, so that every direction of the zone is lit and seen.
void DefaultZone(double covered_min_rad, double covered_max_rad, double margin_deg,
                 double* theta_min_rad, double* theta_max_rad);

}  // namespace zbrdf
