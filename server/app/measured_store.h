// A Store that measures another: each operation's time goes to the store latency histogram,
// and the runs, frames and probe reports passing through it move the run, frame and probe
// metrics (server_metrics.h). It sits between the run manager and the real store when the
// server serves metrics, so that neither the runs nor the store code carries metrics calls.
//
// Runs are counted by the states this replica writes: a run put QUEUED or RUNNING is counted
// in that gauge until the replica writes its final state, which moves it to the ended
// counter (once per run, however many times the final row is written). With several replicas
// on one store a run accepted here may be claimed by another: when this replica reads its
// row (the run manager does, for each run it queued) and finds it no longer QUEUED, the run
// leaves this replica's queued gauge; the replica that claimed it counts it from then on.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "server/app/server_metrics.h"
#include "server/store/store.h"
#include "server/store/store_methods.h"

namespace mbstream {

class MeasuredStore final : public Store {
 public:
  MeasuredStore(std::unique_ptr<Store> store, ServerMetrics& metrics);

  MBSTREAM_STORE_OVERRIDES  // store_methods.h: every method of Store
  void NoteClaimed(const v1::RunInfo& info) override;

 private:
  // Calls `operation` and records its time under `which` (also when it throws).
  template <typename Operation>
  auto Timed(StoreOperation which, Operation operation) const -> decltype(operation());
  // Moves the run's count from the state this replica last wrote to `info`'s state.
  void CountState(const v1::RunInfo& info);
  // A run queued here whose row `stored` says it left the queue without this replica writing
  // it (another replica claimed or ended it): no longer in this replica's queued gauge.
  void ForgetIfTakenElsewhere(const v1::RunInfo& stored) const;

  std::unique_ptr<Store> store_;
  ServerMetrics& metrics_;
  mutable std::mutex mutex_;
  mutable std::map<std::string, v1::RunState> unfinished_;  // run id -> QUEUED or RUNNING
};

}  // namespace mbstream
