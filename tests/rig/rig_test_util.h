// Shared fixtures for the tests of everything that reads a rig (rig/, simulate/, acquisition/,
// calibration/): the shipped rigs, at the fast preset, with their direction maps cached in the
// build tree.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "rig/direction_maps.h"
#include "rig/optics.h"
#include "rig/rig.h"

namespace zbrdf::testing {

inline std::string SourceRig(const std::string& name) {
  return std::string(ZBRDF_SOURCE_DIR) + "/rig/rigs/" + name;
}

// A map cache in the build tree, shared by the test processes (CTest runs each test in its own
// process; writes are atomic renames, so concurrent builders are harmless).
inline std::string TestCacheDir() {
  static const std::string dir = [] {
    const std::string path = std::string(ZBRDF_BINARY_DIR) + "/test-cache";
    std::filesystem::create_directories(path);
    return path;
  }();
  return dir;
}

struct FastThesisRig {
  Rig rig = ApplyPreset(LoadRig(SourceRig("thesis.yaml")), Preset::kFast);
  OpticalSystem optics{rig};
  RigMaps maps = LoadOrBuildRigMaps(optics, TestCacheDir());
};

// Built once per process (tracing the maps takes ~0.5 s).
inline const FastThesisRig& SharedFastThesisRig() {
  static const FastThesisRig rig;
  return rig;
}

}  // namespace zbrdf::testing
