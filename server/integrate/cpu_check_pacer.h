// How many internal steps an integrator takes between two checks of its CPU budget.
#pragma once

#include <algorithm>

#include "server/integrate/thread_cpu_clock.h"

namespace mbstream {

// Up to kMaxSteps steps between checks, fewer when steps are slow, so that a check comes
// about every kInterval_s of (monotonic, hence at least CPU) time: a budget is overrun by at
// most that or one step. A fixed count was not enough: 256 steps of a 100-joint model's
// BDF take 0.5 s in a release build and a minute under AddressSanitizer. The pacer starts at
// one step and learns the cost of a step from each chunk; it allocates nothing.
class CpuCheckPacer {
 public:
  static constexpr long kMaxSteps = 256;
  static constexpr double kInterval_s = 0.01;

  // Steps the next chunk may take, given that `remaining` are left in the step budget.
  long Chunk(long remaining) const { return std::max(1L, std::min(remaining, chunk_)); }

  // Call before a chunk.
  void Start() { start_s_ = MonotonicSeconds(); }

  // Call after a chunk that took `steps` steps: sets the next chunk's length.
  void Finish(long steps) {
    if (steps <= 0) return;
    const double per_step_s = (MonotonicSeconds() - start_s_) / static_cast<double>(steps);
    const double fit = per_step_s > 0.0 ? kInterval_s / per_step_s : double(kMaxSteps);
    chunk_ = std::clamp(static_cast<long>(fit), 1L, kMaxSteps);
  }

 private:
  long chunk_ = 1;
  double start_s_ = 0.0;
};

}  // namespace mbstream
