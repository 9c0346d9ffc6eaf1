// Simulated sessions for the tools tests, made once and shared.
//
// CTest runs every test in its own process, so sessions are cached on disk under the build tree
// (test-sessions/<material>-o<order>), each made under an exclusive file lock, and an incomplete
// folder (a crashed run) is made again. Simulations use the fast preset of the thesis rig, seed 1,
// and the build tree's direction-map cache unless ZBRDF_CACHE_DIR is set.
#pragma once

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "rig/rig.h"
#include "tools/fit_all.h"
#include "tools/virtual_capture.h"

namespace zbrdf::testing {

inline std::string TestBuildDir(const std::string& name) {
  const std::string path = std::string(ZBRDF_BINARY_DIR) + "/" + name;
  std::filesystem::create_directories(path);
  return path;
}

inline std::string ThesisRigPath() { return std::string(ZBRDF_SOURCE_DIR) + "/rig/rigs/thesis.yaml"; }

class FileLock {
 public:
  explicit FileLock(const std::string& path) : fd_(::open(path.c_str(), O_CREAT | O_RDWR, 0644)) {
    if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0) throw std::runtime_error("cannot lock " + path);
  }
  ~FileLock() {
    ::flock(fd_, LOCK_UN);
    ::close(fd_);
  }

 private:
  int fd_;
};

struct SessionOptions {
  double shortest_exposure_us = 0;  // 0: metered
  int exposures = 3;
  std::string tag;                  // distinguishes sessions of one material with other options
};

inline std::string SimulatedSession(const std::string& spec, int order, const SessionOptions& options = {}) {
  ::setenv("ZBRDF_CACHE_DIR", TestBuildDir("test-cache").c_str(), 0);
  const std::string root = TestBuildDir("test-sessions");
  const std::string dir = root + "/" + MaterialFolderName(spec) + "-o" + std::to_string(order) + options.tag;
  FileLock lock(dir + ".lock");
  if (std::filesystem::exists(dir + "/zonal.exr")) return dir;
  std::filesystem::remove_all(dir);  // a crashed run's leftovers (this cache only)
  VirtualCaptureArgs args;
  args.rig = ApplyPreset(LoadRig(ThesisRigPath()), Preset::kFast);
  args.preset_name = "fast";
  args.material_spec = spec;
  args.seed = 1;
  args.job.out_dir = dir;
  args.job.order = order;
  args.job.exposures = options.exposures;
  args.job.shortest_exposure_us = options.shortest_exposure_us;
  args.job.processing.write_hdr_images = false;
  const VirtualCaptureOutcome outcome = RunVirtualCapture(args);
  if (!outcome.result.complete) throw std::runtime_error("simulation of " + spec + " did not complete");
  return dir;
}

}  // namespace zbrdf::testing
