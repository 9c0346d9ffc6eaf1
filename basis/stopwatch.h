// Wall time of the work a user waits for (fit, processing and bench timings in report.json and
// --json output): std::chrono::steady_clock, which never jumps with the system clock.
#pragma once

#include <chrono>

namespace zbrdf {

using WallClock = std::chrono::steady_clock;

// Seconds of wall time since `start`, a WallClock::now().
inline double SecondsSince(WallClock::time_point start) {
  return std::chrono::duration<double>(WallClock::now() - start).count();
}

}  // namespace zbrdf
