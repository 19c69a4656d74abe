// RunManager's view of a sweep (StartSweep's runs under one RunInfo.sweep_id): its runs as
// the store holds them, every replica's (found by the store's index of sweep ids), and the
// mark that it was cancelled.
#include <algorithm>

#include "server/runs/run.h"
#include "server/runs/run_manager.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"

namespace mbstream {

std::vector<v1::RunInfo> RunManager::SweepRuns(const std::string& sweep_id) const {
  std::vector<v1::RunInfo> runs;
  if (sweep_id.empty()) return runs;
  for (v1::RunInfo& stored : store_->ListSweepRuns(sweep_id)) {
    // A run integrating here: its live info (the store's row is updated at its end only).
    if (std::shared_ptr<Run> run = FindActive(stored.id()); run) {
      const bool cancelled = stored.sweep_cancelled();
      stored = run->Info();
      stored.set_sweep_cancelled(stored.sweep_cancelled() || cancelled);
    }
    runs.push_back(std::move(stored));
  }
  std::stable_sort(runs.begin(), runs.end(), [](const v1::RunInfo& a, const v1::RunInfo& b) {
    return a.sweep_point() < b.sweep_point();
  });
  return runs;
}

bool RunManager::SweepCancelled(const std::string& sweep_id) const {
  return !sweep_id.empty() && store_->SweepCancelled(sweep_id);
}

int RunManager::MarkSweepCancelled(const std::string& sweep_id) {
  if (sweep_id.empty()) return 0;
  return store_->MarkSweepCancelled(sweep_id);
}

}  // namespace mbstream
