// The wall clock that paces realtime runs (RunSpec.realtime: a frame at simulated time t goes
// out at wall time start + t / realtime). An interface, so that a test can drive a run's
// pacing frame by frame with a manual clock instead of waiting for real time to pass.
#pragma once

#include <atomic>
#include <chrono>

namespace mbstream {

class RunClock {
 public:
  using TimePoint = std::chrono::steady_clock::time_point;
  virtual ~RunClock() = default;

  virtual TimePoint Now() const = 0;
  // Returns once `due` has come, or soon after `cancel` becomes true.
  virtual void WaitUntil(TimePoint due, const std::atomic<bool>& cancel) = 0;
};

// std::chrono::steady_clock; waits in slices of at most 20 ms so that a cancel is seen soon.
RunClock& SteadyRunClock();

}  // namespace mbstream
