// RunManager: waiting for a run's state to change (GetResult's wait, WatchRun's progress)
// on the changes this replica makes, instead of reading the run again and again.
#include <algorithm>

#include "server/runs/run_manager.h"
#include "server/wire/stats_conversion.h"

namespace mbstream {

void RunManager::NoteStateChange() {
  {
    std::lock_guard<std::mutex> lock(changes_mutex_);
    ++state_changes_;
  }
  state_changed_.notify_all();
  feeder_.Wake();  // a run of a sweep may have ended: its window has room
}

v1::RunInfo RunManager::AwaitChange(const std::string& run_id, v1::RunState from,
                                    std::chrono::steady_clock::time_point until) const {
  // Changes made here wake the wait at once; a run integrating on another replica (shared
  // store) or a claim that failed is read again every kRecheck.
  constexpr auto kRecheck = std::chrono::milliseconds(100);
  for (;;) {
    uint64_t seen = 0;
    {
      std::lock_guard<std::mutex> lock(changes_mutex_);
      seen = state_changes_;  // before reading the run: no change is missed in between
    }
    const auto now = std::chrono::steady_clock::now();
    // A run of this replica is looked at without copying its info (woken by every run's
    // changes, most waits see their run unchanged). One that shows a final state while it is
    // still listed here (Finish between its last UpdateInfo and Release) is waited for until
    // it is gone: whoever is told a run ended then reads it, and its result, as stored.
    if (std::shared_ptr<Run> run = FindActive(run_id);
        run == nullptr || (run->state() != from && !IsFinalState(run->state())) || now >= until) {
      v1::RunInfo info = Get(run_id);
      if (info.state() != from || now >= until) return info;
    }
    // Shutdown (RunQueue) sets its reason and then calls NoteStateChange: no wait misses it.
    auto stopping = [&] { return queue_.stop_reason().has_value(); };
    {
      std::unique_lock<std::mutex> lock(changes_mutex_);
      if (!stopping()) {
        state_changed_.wait_until(lock, std::min(until, now + kRecheck),
                                  [&] { return stopping() || state_changes_ != seen; });
        continue;
      }
    }
    return Get(run_id);  // stopping
  }
}

}  // namespace mbstream
