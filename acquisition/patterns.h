// Projector patterns that light the sample with the zonal basis functions.
//
// To light the sample with radiance L(w) = s Z^+(w) (or s Z^-(w) = s max(0, -Z(w))) over the
// zone, each projector pixel gets the level whose output, after the projector's response
// curve, flat field and black level, is s times the average of Z^+ over the directions that
// pixel covers (3 x 3 points across its footprint, interpolated from the projector's direction
// map; 16 x 16 for a pixel the zone's edge crosses). Averaging over the footprint, rather than taking Z at the pixel center, keeps the
// integral of Z over each pixel's solid angle. The scale s makes the brightest pixel use the
// full range; the quantization to the projector's bit depth is reported per pattern as the
// relative RMS of the realized minus the intended radiance (solid-angle weighted).
//
// Patterns depend only on the plan's zone and order and on the rig calibration; they are cached
// on disk as 16-bit PNGs with a JSON index, keyed by a hash of both.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "acquisition/plan.h"
#include "acquisition/rig_calibration.h"
#include "basis/progress.h"
#include "drivers/projector.h"

namespace zbrdf {

struct LobePatternInfo {
  std::string name;                 // PlannedLobe::Name()
  double radiance_per_unit_z = 0;   // s: sample radiance (W m^-2 sr^-1) per unit of Z
  double quantization_error = 0;    // relative RMS (0 for the dark pattern)
  std::string file;                 // PNG in the pattern cache
};

class PatternSet {
 public:
  // Loads the patterns for (plan, calibration) from cache_dir, or computes and stores them.
  PatternSet(const CapturePlan& plan, const RigCalibration& calibration,
             const std::string& cache_dir, const ProgressCallback& progress = nullptr);

  const std::vector<LobePatternInfo>& lobes() const { return lobes_; }
  // The pattern of plan lobe i, read from the cache (throws InputError if the file is gone or
  // damaged, naming it).
  Pattern Load(int lobe) const;
  double compute_seconds() const { return compute_seconds_; }
  const std::string& folder() const { return folder_; }

 private:
  void Compute(const CapturePlan& plan, const RigCalibration& calibration,
               const ProgressCallback& progress);

  std::string folder_;
  int width_ = 0, height_ = 0, bit_depth_ = 8;
  std::vector<LobePatternInfo> lobes_;
  double compute_seconds_ = 0;
};

// Hash of the inputs that determine the patterns (zone, order, projector geometry, response,
// flat field).
uint64_t PatternKey(const CapturePlan& plan, const RigCalibration& calibration);

}  // namespace zbrdf
