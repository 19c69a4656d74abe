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

namespace mbstream {

class MeasuredStore final : public Store {
 public:
  MeasuredStore(std::unique_ptr<Store> store, ServerMetrics& metrics);

  const std::string& path() const override { return store_->path(); }
  void ReleaseMemory() override { store_->ReleaseMemory(); }
  bool PutModel(const v1::ModelInfo& info, const v1::ModelBundle& bundle) override;
  std::vector<v1::ModelInfo> ListModels() const override;
  std::optional<v1::ModelBundle> GetModelBundle(const std::string& model_id,
                                                bool asset_data) const override;
  std::map<std::string, int64_t> ModelBytes() const override;
  void PutRun(const v1::RunInfo& info) override;
  bool AddRuns(const std::vector<v1::RunInfo>& infos) override;
  std::optional<v1::RunInfo> GetRun(const std::string& run_id) const override;
  std::vector<v1::RunInfo> ListRuns() const override;
  bool PutFrameChunk(const std::string& run_id, int64_t index, const EncodedFrameChunk& chunk,
                     const std::string& holder) override;
  bool FinishRun(const v1::RunInfo& info, int64_t index, const EncodedFrameChunk& last_chunk,
                 const std::string& holder) override;
  void FinishRun(const v1::RunInfo& info, const std::vector<v1::Frame>& frames) override;
  std::optional<int64_t> GetFrameChunkData(const std::string& run_id, int64_t index,
                                           std::string& data) const override;
  void AddProbes(const std::vector<v1::ProbeReport>& reports) override;
  std::vector<v1::ProbeReport> GetProbes(const std::string& run_id) const override;
  std::optional<int64_t> FrameChunkHolding(const std::string& run_id, int64_t seq) const override;
  void CreateProbeSet(const v1::ProbeSet& set) override;
  void AddProbeSetReports(const std::string& set_id,
                          const std::vector<v1::ProbeReport>& reports) override;
  std::vector<v1::ProbeSet> ListProbeSets(const std::string& run_id) const override;
  std::optional<v1::ProbeSet> GetProbeSet(const std::string& set_id) const override;
  std::vector<v1::ProbeReport> GetProbeSetReports(const std::string& set_id) const override;
  int MarkUnfinishedRunsInterrupted(const std::string& message) override;
  std::optional<v1::RunInfo> ClaimQueuedRun(const RunLease& lease) override;
  void NoteClaimed(const v1::RunInfo& info) override;
  bool RenewLease(const std::string& run_id, const std::string& holder,
                  int64_t expires_unix_ms) override;
  std::vector<v1::RunInfo> ReapExpiredLeases(int64_t now_unix_ms,
                                             const std::string& reaper) override;
  std::vector<v1::RunInfo> ListRunningRuns() const override;
  bool PutRunIfHeld(const v1::RunInfo& info, const std::string& holder) override;
  std::optional<v1::RunInfo> EndQueuedRun(const std::string& run_id, v1::RunState state,
                                          const std::string& message, int64_t now_unix_ms) override;

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
