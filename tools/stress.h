// The numerical stability suite (`zbrdf stress`): extreme orders, zones, materials and frames,
// each a named case that must either succeed within a stated tolerance or fail with a clear
// error (InputError, DeviceError or NumericalError from basis/error.h, naming the thing and
// what to do). Never a NaN in an output file, never a crash.
//
// Groups (docs/stress.md lists every case with its tolerance and why):
//   basis    zonal basis and moment-form conversion at orders up to 30, on narrow zones and on
//            zones touching the pole or the horizon: the conversion must truncate, say so, and
//            stay finite
//   hdr      HDR merge of synthetic frames: all black, all saturated, mismatched sizes, values
//            beyond the bit depth, bad exposure times
//   zonal    zonal.exr written and read back with NaN / Inf in values, tensor or variances
//   capture  simulated captures (thesis rig, fast preset, order 2) of extreme materials, then the
//            SH conversion and D-BRDF / GGX fits; every EXR and JSON output checked for NaN
//
// A case runs on its own (RunStressCase) with fixed seeds, so the outcome is reproducible.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "basis/progress.h"

namespace zbrdf {

enum class StressOutcome {
  kPass,           // succeeded within the tolerance
  kExpectedError,  // failed as it should, with a clear InputError / DeviceError / NumericalError
  kFail,           // anything else: a tolerance missed, a NaN written, a wrong or unclear error
};
std::string StressOutcomeName(StressOutcome outcome);  // "pass", "expected-error", "FAIL"

// What a case must do to pass.
enum class StressExpect {
  kSuccess,         // finish, with every check within tolerance
  kInputError,      // throw InputError
  kDeviceError,     // throw DeviceError
  kNumericalError,  // throw NumericalError
  kSuccessOrError,  // either finish within tolerance or throw one of the three (extreme data
                    // where refusing is as good an answer as a result)
};

struct StressOptions {
  // Folder for the sessions and files the cases write (each case in its own subfolder, emptied
  // first). Required by the capture and zonal groups.
  std::string work_dir;
  std::string rig_path;  // rig file of the capture cases ("" : the bundled thesis rig)
  uint64_t seed = 1;
  // Incident directions per camera pixel in the capture cases (0: the fast preset's 1024). The
  // cases stress the range of the numbers, not the frames' Monte Carlo noise, and the default
  // 64 makes a capture take seconds.
  int samples_per_pixel = 64;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct StressCase {
  std::string name;       // e.g. "basis-order30-narrow"
  std::string group;      // basis, hdr, zonal, capture
  std::string what;       // one line: the input and what it exercises
  std::string tolerance;  // one line: what passing means, with the numbers
  StressExpect expect = StressExpect::kSuccess;
  // Runs the case; returns a line of measured values. Throws StressCheckFailed when a check
  // misses its tolerance, and whatever the library throws otherwise.
  std::function<std::string(const StressOptions& options, const std::string& case_dir)> run;
};

// Thrown by a case's own checks.
class StressCheckFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct StressResult {
  std::string name, group, what, tolerance;
  StressOutcome outcome = StressOutcome::kFail;
  std::string error_kind;  // "input", "device", "numerical", "internal", "other" or ""
  std::string detail;      // measured values, the error's message, or what went wrong
  double seconds = 0;

  nlohmann::json ToJson() const;
};

// Every case, in report order.
const std::vector<StressCase>& StressCases();
// The case named `name`; throws InputError listing the names if there is none.
const StressCase& FindStressCase(const std::string& name);

// Runs one case in options.work_dir/<name>. Never throws for what the case does (that is the
// outcome); throws InputError only if the work folder cannot be made.
StressResult RunStressCase(const StressCase& stress_case, const StressOptions& options);

// Runs the cases in order, reporting progress (stage "stress", unit "cases").
std::vector<StressResult> RunStressCases(const std::vector<const StressCase*>& cases,
                                         const StressOptions& options,
                                         const ProgressCallback& progress = {});

// Non-finite values in every channel of every part of an EXR file (any pixel type).
int64_t CountNonFiniteExr(const std::string& path);
// Non-finite numbers anywhere in a JSON value (nlohmann keeps NaN as a number until dumped).
int64_t CountNonFiniteJson(const nlohmann::json& value);

}  // namespace zbrdf
