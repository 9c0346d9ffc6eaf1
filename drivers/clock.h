// Time source for capture sessions: real time on hardware, modeled time on the virtual rig.
//
// The session runner waits (projector settle) and timestamps frames through a Clock, so the
// virtual rig can report the wall time a real capture would take without sleeping.
#pragma once

#include <atomic>
#include <cstdint>

namespace zbrdf {

class Clock {
 public:
  virtual ~Clock() = default;
  virtual int64_t NowUs() const = 0;
  virtual void SleepUs(int64_t duration_us) = 0;
};

// std::chrono::steady_clock and std::this_thread::sleep_for.
class SteadyClock final : public Clock {
 public:
  int64_t NowUs() const override;
  void SleepUs(int64_t duration_us) override;
};

// A clock that only advances when told to; SleepUs advances it without sleeping. Safe to share
// between threads (a virtual camera behind a GigE Vision fake advances it on the fake's thread).
class ModelClock final : public Clock {
 public:
  int64_t NowUs() const override { return now_us_.load(std::memory_order_relaxed); }
  void SleepUs(int64_t duration_us) override {
    now_us_.fetch_add(duration_us, std::memory_order_relaxed);
  }

 private:
  std::atomic<int64_t> now_us_{0};
};

}  // namespace zbrdf
