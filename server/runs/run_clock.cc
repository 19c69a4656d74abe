#include "server/runs/run_clock.h"

#include <algorithm>
#include <thread>

namespace mbstream {

namespace {

class SteadyClock final : public RunClock {
 public:
  TimePoint Now() const override { return std::chrono::steady_clock::now(); }

  void WaitUntil(TimePoint due, const std::atomic<bool>& cancel) override {
    for (TimePoint now = Now(); now < due && !cancel; now = Now()) {
      std::this_thread::sleep_for(
          std::min<std::chrono::steady_clock::duration>(due - now, std::chrono::milliseconds(20)));
    }
  }
};

}  // namespace

RunClock& SteadyRunClock() {
  static SteadyClock clock;
  return clock;
}

}  // namespace mbstream
