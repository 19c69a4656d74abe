#include "server/app/measured_store.h"

#include <chrono>

namespace mbstream {

namespace {

// Records the time from construction to destruction in a histogram, s.
class ScopedTimer {
 public:
  explicit ScopedTimer(metrics::Histogram& histogram)
      : histogram_(histogram), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() {
    histogram_.Observe(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  metrics::Histogram& histogram_;
  std::chrono::steady_clock::time_point start_;
};

bool IsUnfinished(v1::RunState state) { return state == v1::QUEUED || state == v1::RUNNING; }

}  // namespace

MeasuredStore::MeasuredStore(std::unique_ptr<Store> store, ServerMetrics& metrics)
    : store_(std::move(store)), metrics_(metrics) {}

template <typename Operation>
auto MeasuredStore::Timed(StoreOperation which, Operation operation) const
    -> decltype(operation()) {
  ScopedTimer timer(metrics_.store(which));
  return operation();
}

void MeasuredStore::CountState(const v1::RunInfo& info) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto known = unfinished_.find(info.id());
  if (known != unfinished_.end()) {
    if (known->second == info.state()) return;
    metrics_.runs(known->second).Add(-1);
  }
  if (IsUnfinished(info.state())) {
    metrics_.runs(info.state()).Add(1);
    unfinished_[info.id()] = info.state();
  } else if (known != unfinished_.end()) {
    metrics_.runs_ended(info.state()).Add();
    unfinished_.erase(known);
  }
}

void MeasuredStore::ForgetIfTakenElsewhere(const v1::RunInfo& stored) const {
  if (stored.state() == v1::QUEUED) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto known = unfinished_.find(stored.id());
  if (known == unfinished_.end() || known->second != v1::QUEUED) return;
  // A claim of this replica that the store has committed and this replica has not counted
  // yet is counted RUNNING when ClaimQueuedRun returns (the run is unknown here by then). An
  // end this replica has committed and not counted yet (EndQueuedRun) is then not counted as
  // ended here: a read in those microseconds costs one count, never a gauge that stays up.
  metrics_.runs(v1::QUEUED).Add(-1);
  unfinished_.erase(known);
}

const std::string& MeasuredStore::path() const { return store_->path(); }

void MeasuredStore::ReleaseMemory() { store_->ReleaseMemory(); }

bool MeasuredStore::PutModel(const v1::ModelInfo& info, const v1::ModelBundle& bundle) {
  return Timed(StoreOperation::kPutModel, [&] { return store_->PutModel(info, bundle); });
}

std::vector<v1::ModelInfo> MeasuredStore::ListModels() const {
  return Timed(StoreOperation::kListModels, [&] { return store_->ListModels(); });
}

std::optional<v1::ModelBundle> MeasuredStore::GetModelBundle(const std::string& model_id,
                                                             bool asset_data) const {
  return Timed(StoreOperation::kGetModelBundle,
               [&] { return store_->GetModelBundle(model_id, asset_data); });
}

std::map<std::string, int64_t> MeasuredStore::ModelBytes() const {
  return Timed(StoreOperation::kModelBytes, [&] { return store_->ModelBytes(); });
}

void MeasuredStore::PutRun(const v1::RunInfo& info) {
  Timed(StoreOperation::kPutRun, [&] { store_->PutRun(info); });
  CountState(info);
}

bool MeasuredStore::AddRuns(const std::vector<v1::RunInfo>& infos) {
  if (!Timed(StoreOperation::kPutRun, [&] { return store_->AddRuns(infos); })) return false;
  for (const v1::RunInfo& info : infos) CountState(info);
  return true;
}

std::optional<v1::RunInfo> MeasuredStore::GetRun(const std::string& run_id) const {
  std::optional<v1::RunInfo> stored =
      Timed(StoreOperation::kGetRun, [&] { return store_->GetRun(run_id); });
  if (stored) ForgetIfTakenElsewhere(*stored);
  return stored;
}

std::vector<v1::RunInfo> MeasuredStore::ListRuns() const {
  return Timed(StoreOperation::kListRuns, [&] { return store_->ListRuns(); });
}

bool MeasuredStore::PutFrameChunk(const std::string& run_id, int64_t index,
                                  const EncodedFrameChunk& chunk, const std::string& holder) {
  const bool written = Timed(StoreOperation::kPutFrameChunk,
                             [&] { return store_->PutFrameChunk(run_id, index, chunk, holder); });
  if (written) metrics_.frames().Add(static_cast<double>(chunk.frame_count));
  return written;
}

bool MeasuredStore::FinishRun(const v1::RunInfo& info, int64_t index,
                              const EncodedFrameChunk& last_chunk, const std::string& holder) {
  const bool written = Timed(StoreOperation::kFinishRun,
                             [&] { return store_->FinishRun(info, index, last_chunk, holder); });
  if (!written) return false;
  metrics_.frames().Add(static_cast<double>(last_chunk.frame_count));
  CountState(info);
  return true;
}

void MeasuredStore::FinishRun(const v1::RunInfo& info, const std::vector<v1::Frame>& frames) {
  Timed(StoreOperation::kFinishRun, [&] { store_->FinishRun(info, frames); });
  metrics_.frames().Add(static_cast<double>(frames.size()));
  CountState(info);
}

std::optional<int64_t> MeasuredStore::GetFrameChunkData(const std::string& run_id, int64_t index,
                                                        std::string& data) const {
  return Timed(StoreOperation::kGetFrameChunk,
               [&] { return store_->GetFrameChunkData(run_id, index, data); });
}

void MeasuredStore::AddProbes(const std::vector<v1::ProbeReport>& reports) {
  Timed(StoreOperation::kAddProbes, [&] { store_->AddProbes(reports); });
  for (const v1::ProbeReport& report : reports) {
    metrics_.probe_latency().Observe(static_cast<double>(report.latency_us()) * 1e-6);
  }
}

std::vector<v1::ProbeReport> MeasuredStore::GetProbes(const std::string& run_id) const {
  return Timed(StoreOperation::kGetProbes, [&] { return store_->GetProbes(run_id); });
}

std::optional<int64_t> MeasuredStore::FrameChunkHolding(const std::string& run_id,
                                                        int64_t seq) const {
  return Timed(StoreOperation::kFrameChunkHolding,
               [&] { return store_->FrameChunkHolding(run_id, seq); });
}

void MeasuredStore::CreateProbeSet(const v1::ProbeSet& set) {
  Timed(StoreOperation::kCreateProbeSet, [&] { store_->CreateProbeSet(set); });
}

void MeasuredStore::AddProbeSetReports(const std::string& set_id,
                                       const std::vector<v1::ProbeReport>& reports) {
  Timed(StoreOperation::kAddProbeSetReports, [&] { store_->AddProbeSetReports(set_id, reports); });
}

std::vector<v1::ProbeSet> MeasuredStore::ListProbeSets(const std::string& run_id) const {
  return Timed(StoreOperation::kListProbeSets, [&] { return store_->ListProbeSets(run_id); });
}

std::optional<v1::ProbeSet> MeasuredStore::GetProbeSet(const std::string& set_id) const {
  return Timed(StoreOperation::kGetProbeSet, [&] { return store_->GetProbeSet(set_id); });
}

std::vector<v1::ProbeReport> MeasuredStore::GetProbeSetReports(const std::string& set_id) const {
  return Timed(StoreOperation::kGetProbeSetReports,
               [&] { return store_->GetProbeSetReports(set_id); });
}

int MeasuredStore::MarkUnfinishedRunsInterrupted(const std::string& message) {
  const int marked = Timed(StoreOperation::kMarkUnfinishedRunsInterrupted,
                           [&] { return store_->MarkUnfinishedRunsInterrupted(message); });
  metrics_.runs_ended(v1::INTERRUPTED).Add(marked);
  return marked;
}

void MeasuredStore::NoteClaimed(const v1::RunInfo& info) {
  store_->NoteClaimed(info);
  CountState(info);
}

std::optional<v1::RunInfo> MeasuredStore::ClaimQueuedRun(const RunLease& lease) {
  std::optional<v1::RunInfo> claimed =
      Timed(StoreOperation::kClaimQueuedRun, [&] { return store_->ClaimQueuedRun(lease); });
  if (claimed) CountState(*claimed);
  return claimed;
}

bool MeasuredStore::RenewLease(const std::string& run_id, const std::string& holder,
                               int64_t expires_unix_ms) {
  return Timed(StoreOperation::kRenewLease,
               [&] { return store_->RenewLease(run_id, holder, expires_unix_ms); });
}

std::vector<v1::RunInfo> MeasuredStore::ReapExpiredLeases(int64_t now_unix_ms,
                                                          const std::string& reaper) {
  std::vector<v1::RunInfo> reaped = Timed(StoreOperation::kReapExpiredLeases, [&] {
    return store_->ReapExpiredLeases(now_unix_ms, reaper);
  });
  for (const v1::RunInfo& info : reaped) CountState(info);
  return reaped;
}

std::vector<v1::RunInfo> MeasuredStore::ListRunningRuns() const {
  return Timed(StoreOperation::kListRunningRuns, [&] { return store_->ListRunningRuns(); });
}

bool MeasuredStore::PutRunIfHeld(const v1::RunInfo& info, const std::string& holder) {
  const bool written =
      Timed(StoreOperation::kPutRunIfHeld, [&] { return store_->PutRunIfHeld(info, holder); });
  if (written) CountState(info);
  return written;
}

std::optional<v1::RunInfo> MeasuredStore::EndQueuedRun(const std::string& run_id,
                                                       v1::RunState state,
                                                       const std::string& message,
                                                       int64_t now_unix_ms) {
  std::optional<v1::RunInfo> ended = Timed(StoreOperation::kEndQueuedRun, [&] {
    return store_->EndQueuedRun(run_id, state, message, now_unix_ms);
  });
  if (ended) CountState(*ended);
  return ended;
}

bool MeasuredStore::DeleteRun(const std::string& run_id) {
  return Timed(StoreOperation::kDeleteRun, [&] { return store_->DeleteRun(run_id); });
}

int64_t MeasuredStore::DeleteModel(const std::string& model_id) {
  return Timed(StoreOperation::kDeleteModel, [&] { return store_->DeleteModel(model_id); });
}

bool MeasuredStore::SetRunKeep(const std::string& run_id, bool keep) {
  return Timed(StoreOperation::kSetRunKeep, [&] { return store_->SetRunKeep(run_id, keep); });
}

bool MeasuredStore::AddSweep(const StoredSweep& sweep) {
  return Timed(StoreOperation::kAddSweep, [&] { return store_->AddSweep(sweep); });
}

std::optional<StoredSweep> MeasuredStore::GetSweep(const std::string& sweep_id,
                                                   bool definition) const {
  return Timed(StoreOperation::kGetSweep, [&] { return store_->GetSweep(sweep_id, definition); });
}

std::vector<StoredSweep> MeasuredStore::ListOpenSweeps() const {
  return Timed(StoreOperation::kListOpenSweeps, [&] { return store_->ListOpenSweeps(); });
}

SweepFeed MeasuredStore::AddSweepRuns(const std::string& sweep_id,
                                      const std::vector<v1::RunInfo>& infos) {
  const SweepFeed fed =
      Timed(StoreOperation::kAddSweepRuns, [&] { return store_->AddSweepRuns(sweep_id, infos); });
  if (fed == SweepFeed::kAdded) {
    for (const v1::RunInfo& info : infos) CountState(info);
  }
  return fed;
}

std::vector<v1::RunInfo> MeasuredStore::ListSweepRuns(const std::string& sweep_id, int first_point,
                                                      int max_runs, bool unfinished_only) const {
  return Timed(StoreOperation::kListSweepRuns, [&] {
    return store_->ListSweepRuns(sweep_id, first_point, max_runs, unfinished_only);
  });
}

Store::StateCounts MeasuredStore::CountSweepRuns(const std::string& sweep_id) const {
  return Timed(StoreOperation::kCountSweepRuns, [&] { return store_->CountSweepRuns(sweep_id); });
}

std::vector<v1::RunInfo> MeasuredStore::ListUnfinishedSweepRuns() const {
  return Timed(StoreOperation::kListUnfinishedSweepRuns,
               [&] { return store_->ListUnfinishedSweepRuns(); });
}

bool MeasuredStore::SweepCancelled(const std::string& sweep_id) const {
  return Timed(StoreOperation::kSweepCancelled, [&] { return store_->SweepCancelled(sweep_id); });
}

int MeasuredStore::MarkSweepCancelled(const std::string& sweep_id) {
  return Timed(StoreOperation::kMarkSweepCancelled,
               [&] { return store_->MarkSweepCancelled(sweep_id); });
}

// An operator's occasional calls (GetStorage, BackupStorage): passed on, not timed.
StoreUsage MeasuredStore::Usage(const std::vector<std::string>& weigh_runs) const {
  return store_->Usage(weigh_runs);
}

StoreBackup MeasuredStore::Backup(const std::string& dir) { return store_->Backup(dir); }

}  // namespace mbstream
