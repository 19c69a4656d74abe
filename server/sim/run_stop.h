// The one place that words how a run stops early: cancelled, or failed with a status.
#pragma once

#include <string>

#include "server/sim/run_result.h"

namespace mbstream {

// "cancelled at t = <t_reached> s".
std::string CancelledMessage(double t_reached);

// Stops the run as cancelled at its last good frame (stats->t_reached).
void StopCancelled(RunStats* stats);

// Stops the run with `status` (not kFinished) and `message` (what happened, what to try).
void StopRun(RunStats* stats, RunStatus status, std::string message);

}  // namespace mbstream
