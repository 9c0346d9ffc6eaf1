// Shared by the acquisition tests: per-test temporary folders and the thesis rig (fast preset)
// simulated for a material, with the nominal calibration, ready to run capture jobs.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "acquisition/capture_job.h"
#include "acquisition/rig_calibration.h"
#include "brdf/material_spec.h"
#include "rig/rig.h"
#include "simulate/virtual_rig.h"
#include "tests/rig/rig_test_util.h"

namespace zbrdf::testing {

// temp/zbrdf-<prefix>-<pid>-<name>, removed if it exists (not created).
inline std::string FreshTempDir(const std::string& prefix, const std::string& name) {
  std::string leaf = "zbrdf-" + prefix + "-";
  leaf += std::to_string(::getpid());
  leaf += "-";
  leaf += name;
  const std::string dir = (std::filesystem::temp_directory_path() / leaf).string();
  std::filesystem::remove_all(dir);
  return dir;
}

// A 16 x 8 RGGB frame of 12-bit samples base, base + 1, ...: for the session folder's writers.
inline Frame SmallFrame(uint16_t base) {
  Frame f;
  f.width = 16;
  f.height = 8;
  f.layout = PixelLayout::kBayerRGGB;
  f.bit_depth = 12;
  f.exposure_us = 500;
  for (int i = 0; i < 16 * 8; ++i) f.data.push_back(static_cast<uint16_t>(base + i));
  return f;
}

struct SimulatedRig {
  Rig rig = ApplyPreset(LoadRig(SourceRig("thesis.yaml")), Preset::kFast);
  std::unique_ptr<VirtualRig> virtual_rig;
  RigCalibration calibration;

  explicit SimulatedRig(const std::string& material, bool noise = true) {
    VirtualRig::Options o;
    o.seed = 1;
    o.noise = noise;
    o.cache_dir = TestCacheDir();
    virtual_rig = std::make_unique<VirtualRig>(rig, MakeBrdf(material), o);
    calibration = NominalCalibration(virtual_rig->rig(), virtual_rig->maps());
  }
  // Runs the job on the virtual rig; `seconds`, if given, receives the capture's rig time.
  CaptureJobResult Run(CaptureJobOptions options, double* seconds = nullptr) {
    options.pattern_cache_dir = TestCacheDir();
    const int64_t start = virtual_rig->clock().NowUs();
    CaptureJobResult r = RunCaptureJob(virtual_rig->rig(), calibration, virtual_rig->camera(),
                                       virtual_rig->projector(), virtual_rig->clock(), options);
    if (seconds) *seconds = (virtual_rig->clock().NowUs() - start) * 1e-6;
    return r;
  }
  Camera& camera() { return virtual_rig->camera(); }
};

}  // namespace zbrdf::testing
