#include "server/service/sweep_progress.h"

#include <algorithm>

#include "server/wire/stats_conversion.h"

namespace mbstream {

v1::SweepProgress SweepProgressOf(const std::string& sweep_id, const RunSweeps::View& view,
                                  int runs_from) {
  v1::SweepProgress progress;
  progress.set_sweep_id(sweep_id);
  int runs = 0, ended = 0;
  for (const auto& [state, count] : view.states) {
    if (count <= 0) continue;
    v1::SweepStateCount& entry = *progress.add_states();
    entry.set_state(static_cast<v1::RunState>(state));
    entry.set_runs(count);
    runs += count;
    if (IsFinalState(static_cast<v1::RunState>(state))) ended += count;
  }
  progress.set_ended_runs(ended);
  for (const std::string& path : view.paths) progress.add_paths(path);
  if (view.stored) {
    progress.set_model_id(view.stored->model_id);
    progress.set_total_points(view.stored->total_points);
    progress.set_started_runs(view.stored->next_point);
    progress.set_cancelled(view.stored->cancelled);
    progress.set_window(view.stored->window);
    progress.set_runs_from(std::max(0, runs_from));
  } else {  // started in slices by an older server: every run is in view.runs
    int total = 0;
    for (const v1::RunInfo& run : view.runs) {
      total = std::max(total, run.sweep_points());
      if (run.sweep_cancelled()) progress.set_cancelled(true);
    }
    if (!view.runs.empty()) progress.set_model_id(view.runs.front().model_id());
    progress.set_total_points(std::max(total, runs));
    progress.set_started_runs(runs);
  }
  for (size_t i = 0; i < view.runs.size(); ++i) {
    progress.add_run_ids(view.runs[i].id());
    v1::SweepPoint& point = *progress.add_points();
    if (i < view.values.size()) {
      for (const std::string& value : view.values[i]) point.add_values(value);
    }
  }
  return progress;
}

}  // namespace mbstream
