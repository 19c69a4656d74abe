// A RunClock that moves only when the test says so: a realtime run's frames then go out one
// by one as the test advances the clock, and the test can wait until the run is waiting.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>

#include "server/runs/run_clock.h"

namespace mbstream::testing {

class ManualRunClock : public RunClock {
 public:
  TimePoint Now() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    return now_;
  }

  // Blocks until the clock reaches `due` (Advance) or `cancel` is set. `cancel` is set by
  // other threads without notifying this clock, so it is looked at every millisecond.
  void WaitUntil(TimePoint due, const std::atomic<bool>& cancel) override {
    std::unique_lock<std::mutex> lock(mutex_);
    waiting_for_ = due;
    changed_.notify_all();
    while (now_ < due && !cancel) changed_.wait_for(lock, std::chrono::milliseconds(1));
    waiting_for_.reset();
    changed_.notify_all();
  }

  void Advance(std::chrono::nanoseconds step) {
    std::lock_guard<std::mutex> lock(mutex_);
    now_ += step;
    changed_.notify_all();
  }

  // Waits until a run waits for a time still to come, and returns that time: everything due
  // up to now has been sent. nullopt when nothing waits within `timeout` (a test failure).
  std::optional<TimePoint> WaitForWaiter(std::chrono::seconds timeout = std::chrono::seconds(30)) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!changed_.wait_for(lock, timeout,
                           [&] { return waiting_for_.has_value() && *waiting_for_ > now_; })) {
      return std::nullopt;
    }
    return waiting_for_;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  TimePoint now_{};  // starts at the clock's epoch
  std::optional<TimePoint> waiting_for_;
};

}  // namespace mbstream::testing
