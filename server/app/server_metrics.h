// The server's metrics for operators (issue 16), in one registry scraped at --metrics
// host:port: runs queued and running on this replica, runs ended by final state, frames
// stored, probe round-trip latency, store operation latency, open subscriber streams and build
// info. Names follow the Prometheus conventions (base units in the name, counters end in
// _total). MeasuredStore (measured_store.h) feeds the run, frame, probe and store metrics;
// the subscriber gauge is read from the run manager at scrape time.
#pragma once

#include <array>
#include <functional>

#include "mbstream/v1/run.pb.h"
#include "server/metrics/metric_registry.h"

namespace mbstream {

// The store operations timed, one label value each.
enum class StoreOperation {
  kPutModel,
  kListModels,
  kGetModelBundle,
  kModelBytes,
  kPutRun,
  kGetRun,
  kListRuns,
  kPutFrameChunk,
  kFinishRun,
  kGetFrameChunk,
  kAddProbes,
  kGetProbes,
  kFrameChunkHolding,
  kCreateProbeSet,
  kAddProbeSetReports,
  kListProbeSets,
  kGetProbeSet,
  kGetProbeSetReports,
  kMarkUnfinishedRunsInterrupted,
  kClaimQueuedRun,
  kRenewLease,
  kReapExpiredLeases,
  kPutRunIfHeld,
  kEndQueuedRun,
  kListRunningRuns,
  kDeleteRun,
  kDeleteModel,
  kSetRunKeep,
  kListSweepRuns,
  kMarkSweepCancelled,
  kSweepCancelled,
  kAddSweep,
  kGetSweep,
  kListOpenSweeps,
  kAddSweepRuns,
  kCountSweepRuns,
  kListUnfinishedSweepRuns,
  kCount
};

class ServerMetrics {
 public:
  // Adds the server's families to `registry` (which must outlive this object).
  explicit ServerMetrics(metrics::Registry& registry);

  metrics::Gauge& runs(v1::RunState state);  // QUEUED or RUNNING
  // Counter of runs that ended in `state` (a final state; others count as FAILED).
  metrics::Counter& runs_ended(v1::RunState state);
  metrics::Counter& frames() { return *frames_; }
  metrics::Histogram& probe_latency() { return *probe_latency_; }
  metrics::Histogram& store(StoreOperation operation) {
    return *store_[static_cast<size_t>(operation)];
  }
  // The open Subscribe and WatchRun streams, read when scraped.
  void SetSubscriberCount(std::function<double()> read);

 private:
  metrics::Registry& registry_;
  metrics::Gauge* queued_ = nullptr;
  metrics::Gauge* running_ = nullptr;
  std::array<metrics::Counter*, v1::RunState_ARRAYSIZE> ended_{};
  metrics::Counter* frames_ = nullptr;
  metrics::Histogram* probe_latency_ = nullptr;
  std::array<metrics::Histogram*, static_cast<size_t>(StoreOperation::kCount)> store_{};
};

}  // namespace mbstream
