#include "server/sim/run_stop.h"

#include <utility>

namespace mbstream {

std::string CancelledMessage(double t_reached) {
  return "cancelled at t = " + std::to_string(t_reached) + " s";
}

void StopCancelled(RunStats* stats) {
  StopRun(stats, RunStatus::kCancelled, CancelledMessage(stats->t_reached));
}

void StopRun(RunStats* stats, RunStatus status, std::string message) {
  stats->status = status;
  stats->message = std::move(message);
}

}  // namespace mbstream
