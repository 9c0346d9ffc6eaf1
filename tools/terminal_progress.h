// A one-line progress bar on stderr with units done, rate and ETA.
#pragma once

#include <chrono>
#include <string>

#include "basis/progress.h"

namespace zbrdf {

class TerminalProgress {
 public:
  // quiet: draw nothing (for --json runs, whose stdout must stay machine-readable; the bar goes
  // to stderr anyway, but quiet also keeps logs clean).
  explicit TerminalProgress(bool quiet = false);
  ~TerminalProgress();

  void Update(const Progress& progress);
  ProgressCallback Callback();

 private:
  bool quiet_;
  bool is_tty_;
  std::string stage_;
  std::chrono::steady_clock::time_point stage_start_;
  std::chrono::steady_clock::time_point last_draw_;
  bool line_open_ = false;
};

}  // namespace zbrdf
