// Progress reporting for long work (captures, simulations, batch fits).
//
// Libraries report through a ProgressCallback; the CLI draws a bar with frames done and ETA
// (tools/terminal_progress.h). A null callback means nobody is listening.
#pragma once

#include <functional>
#include <string>

namespace zbrdf {

struct Progress {
  std::string stage;    // what is being done, e.g. "capture", "hdr", "simulate"
  long done = 0;        // units finished
  long total = 0;       // units in all (0 if unknown)
  std::string unit;     // "frames", "materials", ...
};

using ProgressCallback = std::function<void(const Progress&)>;

inline void Report(const ProgressCallback& callback, const Progress& progress) {
  if (callback) callback(progress);
}

}  // namespace zbrdf
