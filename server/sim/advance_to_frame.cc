#include "server/sim/advance_to_frame.h"

#include "server/sim/run_stop.h"

namespace mbstream {

bool AdvanceToFrame(Integrator& integrator, const std::vector<double>& times, size_t k, double* y,
                    RunStats* stats, const std::string& advice, double* t_stop) {
  if (k == 0) return true;
  const AdvanceResult advance = integrator.AdvanceTo(times[k], y);
  if (advance.status != IntegratorStatus::kOk) {
    StopRun(stats, ToRunStatus(advance.status), advance.message + advice);
    if (t_stop) *t_stop = advance.t;
    return false;
  }
  return true;
}

}  // namespace mbstream
