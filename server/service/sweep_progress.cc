#include "server/service/sweep_progress.h"

#include <algorithm>
#include <map>

#include "server/wire/stats_conversion.h"

namespace mbstream {

v1::SweepProgress SweepProgressOf(const std::string& sweep_id,
                                  const std::vector<v1::RunInfo>& runs) {
  v1::SweepProgress progress;
  progress.set_sweep_id(sweep_id);
  std::map<int, int> states;  // by v1::RunState, in the enum's order
  int total = 0, ended = 0;
  for (const v1::RunInfo& run : runs) {
    if (progress.model_id().empty()) progress.set_model_id(run.model_id());
    total = std::max(total, run.sweep_points());
    if (IsFinalState(run.state())) ++ended;
    ++states[run.state()];
    progress.add_run_ids(run.id());
  }
  progress.set_total_points(std::max(total, static_cast<int>(runs.size())));
  progress.set_started_runs(static_cast<int>(runs.size()));
  progress.set_ended_runs(ended);
  for (const auto& [state, count] : states) {
    v1::SweepStateCount& entry = *progress.add_states();
    entry.set_state(static_cast<v1::RunState>(state));
    entry.set_runs(count);
  }
  progress.set_cancelled(SweepWasCancelled(runs));
  return progress;
}

bool SweepWasCancelled(const std::vector<v1::RunInfo>& runs) {
  return std::any_of(runs.begin(), runs.end(),
                     [](const v1::RunInfo& run) { return run.sweep_cancelled(); });
}

}  // namespace mbstream
