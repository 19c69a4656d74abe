// The step between output frames, shared by the integrating formulations' frame sources.
#pragma once

#include <string>
#include <vector>

#include "server/integrate/integrator.h"
#include "server/sim/run_result.h"

namespace mbstream {

// For k > 0, advances `integrator` to times[k] (k = 0 is the start: nothing to do). Returns
// false, with the status and message (plus `advice`) in `stats`, when the run must stop
// there; `t_stop`, if given, then receives the integrator's last good time (y holds the
// state there).
bool AdvanceToFrame(Integrator& integrator, const std::vector<double>& times, size_t k, double* y,
                    RunStats* stats, const std::string& advice = "", double* t_stop = nullptr);

}  // namespace mbstream
