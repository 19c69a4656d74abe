#include "server/sim/advance_to_frame.h"

namespace mbstream {

bool AdvanceToFrame(Integrator& integrator, const std::vector<double>& times, size_t k, double* y,
                    const std::atomic<bool>* cancel, RunStats* stats, const std::string& advice,
                    double* t_stop) {
  if (cancel && cancel->load(std::memory_order_relaxed)) {
    stats->status = RunStatus::kCancelled;
    stats->message = "cancelled at t = " + std::to_string(stats->t_reached) + " s";
    return false;
  }
  if (k == 0) return true;
  const AdvanceResult advance = integrator.AdvanceTo(times[k], y);
  if (advance.status != IntegratorStatus::kOk) {
    stats->status = ToRunStatus(advance.status);
    stats->message = advance.message + advice;
    if (t_stop) *t_stop = advance.t;
    return false;
  }
  return true;
}

}  // namespace mbstream
