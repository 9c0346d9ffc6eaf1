#include "drivers/clock.h"

#include <chrono>
#include <thread>

namespace zbrdf {

int64_t SteadyClock::NowUs() const {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void SteadyClock::SleepUs(int64_t duration_us) {
  if (duration_us > 0) std::this_thread::sleep_for(std::chrono::microseconds(duration_us));
}

}  // namespace zbrdf
