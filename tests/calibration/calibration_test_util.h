// A simulated rig for the calibration tests: the thesis rig at the fast preset as designed, and
// as built (with injected faults), its virtual devices, and target placement by material swap.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "brdf/material_spec.h"
#include "calibration/calibrate.h"
#include "simulate/virtual_rig.h"
#include "tests/acquisition/acquisition_test_util.h"
#include "tests/rig/rig_test_util.h"

namespace zbrdf::testing {

inline std::string TempFolder(const std::string& name) { return FreshTempDir("calibration-test", name); }

struct SimulatedCalibrationRig {
  Rig design = ApplyPreset(LoadRig(SourceRig("thesis.yaml")), Preset::kFast);
  Rig as_built;
  std::unique_ptr<VirtualRig> virtual_rig;
  CalibrationRig rig;
  Target current = Target::kWhite;
  int target_changes = 0;

  // `faults`: a rig overlay (YAML) applied to the design to make the rig as built.
  explicit SimulatedCalibrationRig(const std::string& faults = "", bool noise = true,
                                   uint64_t seed = 7) {
    as_built = faults.empty() ? design : ApplyRigOverlayText(design, faults, "test faults");
    VirtualRig::Options o;
    o.seed = seed;
    o.noise = noise;
    o.cache_dir = TestCacheDir();
    virtual_rig = std::make_unique<VirtualRig>(as_built, MakeBrdf(TargetMaterialSpec(current)), o);
    rig.camera = &virtual_rig->camera();
    rig.projector = &virtual_rig->projector();
    rig.clock = &virtual_rig->clock();
    rig.settle_us = design.timing.projector_settle_ms * 1e3;
    rig.place_target = [this](Target t) {
      if (t == current) return;
      current = t;
      ++target_changes;
      virtual_rig->SetMaterial(MakeBrdf(TargetMaterialSpec(t)));
    };
  }
  // The design rig's nominal calibration (what is known before calibrating).
  RigCalibration Nominal() const {
    const OpticalSystem optics(design);
    return NominalCalibration(design, LoadOrBuildRigMaps(optics, TestCacheDir()));
  }
  // The truth: the as-built rig's own nominal calibration.
  RigCalibration Truth() const {
    const OpticalSystem optics(as_built);
    return NominalCalibration(as_built, LoadOrBuildRigMaps(optics, TestCacheDir()));
  }
  CalibrateOptions Options(const std::string& folder) const {
    CalibrateOptions o;
    o.folder = folder;
    o.cache_dir = TestCacheDir();
    return o;
  }
};

}  // namespace zbrdf::testing
