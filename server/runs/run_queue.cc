// RunQueue: the runs queued and integrating here, new runs queued, cancelled, attached to,
// draining and shutdown. Claims, workers and the keeper: run_queue_leases.cc.
#include "server/runs/run_queue.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "server/runs/request_error.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"
#include "shared/common/check.h"

namespace mbstream {

RunQueue::RunQueue(Store* store, ReplicaOptions replica, const ServerLimits& limits, Hooks hooks,
                   const RunClock* lease_clock)
    : store_(store),
      workers_count_(limits.workers),
      max_queued_runs_(limits.max_queued_runs),
      hooks_(std::move(hooks)),
      lease_clock_(lease_clock),
      replica_(std::move(replica)) {
  MBSTREAM_CHECK(store_ != nullptr && workers_count_ > 0 && !replica_.id.empty());
  MBSTREAM_CHECK(replica_.lease_timeout_s > 0.0 && replica_.claim_poll_s > 0.0);
  MBSTREAM_CHECK(hooks_.new_run_id && hooks_.prepare && hooks_.execute && hooks_.state_changed);
  if (replica_.private_store) {
    const int interrupted = store_->MarkUnfinishedRunsInterrupted(
        "the server stopped while this run was queued or running; start it again");
    if (interrupted > 0) {
      spdlog::warn("{} runs of a previous server marked INTERRUPTED", interrupted);
    }
    RequeueSweepRuns();
  }
  spdlog::info("replica {}: leases of {} s", replica_.id, replica_.lease_timeout_s);
  for (int i = 0; i < workers_count_; ++i) workers_.emplace_back([this] { WorkerLoop(); });
  keeper_ = std::thread([this] { KeeperLoop(); });
}

RunQueue::~RunQueue() { Shutdown("the server stopped"); }

void RunQueue::RequeueSweepRuns() {
  // A run that brought its server down each time it ran is not run a fourth time.
  constexpr int kMaxSweepRestarts = 3;
  int requeued = 0;
  for (v1::RunInfo& info : store_->ListUnfinishedSweepRuns()) {
    if (info.attempts() >= kMaxSweepRestarts) {
      store_->EndQueuedRun(info.id(), v1::INTERRUPTED,
                           "the server stopped " + std::to_string(kMaxSweepRestarts) +
                               " times while this run of sweep " + info.sweep_id() +
                               " was queued or running; start it again",
                           NowMs());
      continue;
    }
    info.set_state(v1::QUEUED);
    info.set_attempts(info.attempts() + 1);
    info.set_started_unix_ms(0);
    info.set_replica("");
    info.set_replica_address("");
    std::shared_ptr<Run> run;
    try {
      store_->PutRun(info);
      run = hooks_.prepare(info);
    } catch (const std::exception& error) {
      spdlog::error("run {} of sweep {}: cannot be queued again: {}", info.id(), info.sweep_id(),
                    error.what());
      store_->EndQueuedRun(info.id(), v1::FAILED,
                           std::string("the server restarted and could not queue the run "
                                       "again: ") +
                               error.what(),
                           NowMs());
      continue;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    active_[info.id()] = run;
    queue_.push_back(run);
    ++wakeups_;
    ++requeued;
  }
  if (requeued > 0) {
    spdlog::warn("{} runs of sweeps a previous server left queued or running queued again",
                 requeued);
  }
}

int RunQueue::Room() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::max(0, max_queued_runs_ - static_cast<int>(queue_.size()));
}

std::vector<std::shared_ptr<Run>> RunQueue::Reserve(
    std::vector<v1::RunInfo>& infos,
    const std::function<std::shared_ptr<Run>(const v1::RunInfo&, size_t)>& make_run) {
  const int count = static_cast<int>(infos.size());
  for (;;) {
    for (v1::RunInfo& info : infos) info.set_id(hooks_.new_run_id());
    std::lock_guard<std::mutex> lock(mutex_);
    CheckAccepting(count);
    std::set<std::string> ids;
    for (const v1::RunInfo& info : infos) {
      if (active_.count(info.id()) || !ids.insert(info.id()).second) break;
    }
    if (static_cast<int>(ids.size()) < count) continue;  // an id taken meanwhile: new ids
    std::vector<std::shared_ptr<Run>> runs(infos.size());
    for (size_t i = 0; i < infos.size(); ++i) {
      runs[i] = make_run(infos[i], i);
      active_[infos[i].id()] = runs[i];
      queue_.push_back(runs[i]);
      unstored_.insert(runs[i].get());
    }
    return runs;
  }
}

void RunQueue::Forget(const std::vector<std::shared_ptr<Run>>& runs) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const std::shared_ptr<Run>& run : runs) {
    unstored_.erase(run.get());
    queue_.erase(std::remove(queue_.begin(), queue_.end(), run), queue_.end());
    if (auto found = active_.find(run->id()); found != active_.end() && found->second == run) {
      active_.erase(found);
    }
  }
}

std::vector<std::shared_ptr<Run>> RunQueue::Enqueue(
    std::vector<v1::RunInfo>& infos,
    const std::function<std::shared_ptr<Run>(const v1::RunInfo&, size_t)>& make_run,
    const StoreRuns& store_runs) {
  // No lock across the store's I/O: new ids are reserved in active_ and queue_ under the lock
  // (counting against the queue limit), stored QUEUED in one transaction that refuses an id
  // already stored by any replica (from then on any replica may claim them; a taken id: new
  // ids for all, again), and the workers woken.
  std::vector<std::shared_ptr<Run>> runs;
  constexpr int kIdAttempts = 100;  // each fails with odds of about 1e-6 (NewTimedId)
  for (int attempt = 1;; ++attempt) {
    runs = Reserve(infos, make_run);
    bool stored = false;
    try {
      stored = store_runs ? store_runs(infos) : store_->AddRuns(infos);
    } catch (...) {
      Forget(runs);
      throw;
    }
    if (stored) break;
    Forget(runs);
    MBSTREAM_CHECK_MSG(attempt < kIdAttempts, "no free run ids after 100 attempts");
  }
  MakeClaimable(infos, runs);
  if (runs.size() == 1) {
    work_.notify_one();
  } else {
    work_.notify_all();
  }
  return runs;
}

void RunQueue::MakeClaimable(const std::vector<v1::RunInfo>& infos,
                             const std::vector<std::shared_ptr<Run>>& runs) {
  std::string stop_reason;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const std::shared_ptr<Run>& run : runs) unstored_.erase(run.get());
    if (stopping_) stop_reason = stop_reason_;
    ++wakeups_;
  }
  if (stop_reason.empty()) return;
  // The queue began to stop while the runs were being stored.
  std::vector<std::shared_ptr<Run>> ended;
  for (size_t i = 0; i < infos.size(); ++i) {
    if (store_->EndQueuedRun(infos[i].id(), v1::INTERRUPTED,
                             stop_reason + " before this run started", NowMs())) {
      ended.push_back(runs[i]);
    }
  }
  if (!ended.empty()) {
    Forget(ended);
    throw RequestError(RequestErrorKind::kUnavailable,
                       "the server is shutting down; start the run on another server");
  }
}

void RunQueue::CheckAccepting(int runs) const {
  if (stopping_) {
    throw RequestError(RequestErrorKind::kUnavailable,
                       "the server is shutting down; start the run on another server");
  }
  if (draining_) {
    throw RequestError(RequestErrorKind::kUnavailable,
                       "this replica is draining (shutting down); start the run on another one");
  }
  if (static_cast<int>(queue_.size()) + runs > max_queued_runs_) {
    throw RequestError(
        RequestErrorKind::kResourceExhausted,
        runs == 1 ? "the run queue is full (" + std::to_string(max_queued_runs_) +
                        " runs waiting); wait for runs to finish or cancel some"
                  : "the run queue has room for " +
                        std::to_string(max_queued_runs_ - static_cast<int>(queue_.size())) +
                        " of these " + std::to_string(runs) +
                        " runs; wait for runs to finish, or start fewer");
  }
}

std::shared_ptr<Run> RunQueue::Find(const std::string& run_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto found = active_.find(run_id);
  return found == active_.end() ? nullptr : found->second;
}

bool RunQueue::IntegratesHere(const std::string& run_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto found = active_.find(run_id);
  return found != active_.end() &&
         std::find(queue_.begin(), queue_.end(), found->second) == queue_.end();
}

std::vector<v1::RunInfo> RunQueue::SweepInfos(const std::string& sweep_id) const {
  std::vector<v1::RunInfo> infos;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, run] : active_) {
    v1::RunInfo info = run->Info();
    if (info.sweep_id() == sweep_id) infos.push_back(std::move(info));
  }
  return infos;
}

std::shared_ptr<Run> RunQueue::NewestRunning() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::shared_ptr<Run> running;
  int64_t running_since = 0;
  for (const auto& [id, run] : active_) {
    const v1::RunInfo info = run->Info();
    if (info.state() == v1::RUNNING && (!running || info.started_unix_ms() > running_since)) {
      running = run;
      running_since = info.started_unix_ms();
    }
  }
  return running;
}

void RunQueue::Release(const std::shared_ptr<Run>& run) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (auto found = active_.find(run->id()); found != active_.end() && found->second == run) {
      active_.erase(found);
    }
  }
  idle_.notify_all();
}

std::optional<v1::RunInfo> RunQueue::Cancel(const std::string& run_id) {
  std::shared_ptr<Run> run = Find(run_id);
  bool queued_here = false, dequeued = false;
  if (run) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto queued = std::find(queue_.begin(), queue_.end(), run);
    queued_here = queued != queue_.end();
    // A private store's claims are made in queue_ (ClaimPrivate), not in the store: taken
    // out of it here, no worker claims the run while its row is ended.
    if (queued_here && replica_.private_store && !unstored_.count(run.get())) {
      queue_.erase(queued);
      dequeued = true;
    }
  }
  if (run && !queued_here) {  // integrating here
    run->cancel = true;
    spdlog::info("run {} cancel requested", run_id);
    return run->Info();
  }
  if (dequeued) return CancelDequeued(run);
  // Queued (here or by another replica): ended in the store unless a replica claimed it.
  if (std::optional<v1::RunInfo> ended =
          store_->EndQueuedRun(run_id, v1::CANCELLED, "cancelled before it started", NowMs())) {
    if (run) EndPlaceholder(run, *ended);
    spdlog::info("run {} cancelled before it started", run_id);
    return *ended;
  }
  if (run = Find(run_id); run) {  // claimed by a worker of this replica meanwhile
    run->cancel = true;
    return run->Info();
  }
  return std::nullopt;
}

v1::RunInfo RunQueue::CancelDequeued(const std::shared_ptr<Run>& run) {
  std::optional<v1::RunInfo> ended;
  try {
    ended = store_->EndQueuedRun(run->id(), v1::CANCELLED, "cancelled before it started", NowMs());
  } catch (const std::exception& error) {
    spdlog::error("run {}: storing its cancellation failed: {}", run->id(), error.what());
  }
  if (!ended) {  // a worker ends it CANCELLED instead (RunManager::Execute), storing it again
    run->cancel = true;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.push_front(run);
      ++wakeups_;
    }
    work_.notify_one();
    return run->Info();
  }
  EndPlaceholder(run, *ended);
  spdlog::info("run {} cancelled before it started", run->id());
  return *ended;
}

void RunQueue::EndPlaceholder(const std::shared_ptr<Run>& run, const v1::RunInfo& info) {
  run->UpdateInfo([&](v1::RunInfo& live) { live = info; });
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.erase(std::remove(queue_.begin(), queue_.end(), run), queue_.end());
    if (auto found = active_.find(run->id()); found != active_.end() && found->second == run) {
      active_.erase(found);
    }
    if (auto found = elsewhere_.find(run->id());
        found != elsewhere_.end() && found->second == run) {
      elsewhere_.erase(found);
    }
  }
  run->End();
  hooks_.state_changed();
}

RunQueue::Attached RunQueue::Attach(const std::shared_ptr<Subscription>& subscriber,
                                    const std::string& run_id, bool send_started) {
  if (std::shared_ptr<Run> run = Find(run_id)) {
    run->Attach(subscriber, send_started);
    return Attached::kAttached;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (auto found = elsewhere_.find(run_id); found != elsewhere_.end()) {
      found->second->Attach(subscriber, send_started);  // ended when the store shows it ended
      return Attached::kAttached;
    }
  }
  std::optional<v1::RunInfo> stored = store_->GetRun(run_id);
  if (!stored) return Attached::kNotFound;
  // Claimed here a moment ago (a proxied subscriber comes as soon as the claim is stored).
  if (std::shared_ptr<Run> run = AwaitClaimedHere(std::move(*stored))) {
    run->Attach(subscriber, send_started);
    return Attached::kAttached;
  }
  return Attached::kNotHere;
}

std::shared_ptr<Run> RunQueue::AwaitClaimedHere(v1::RunInfo stored) {
  // Woken by each claim the workers prepare; the store is read again then and every
  // kRecheck (a failed preparation is stored FAILED, a lost lease reaped).
  constexpr auto kRecheck = std::chrono::milliseconds(100);
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    if (auto it = active_.find(stored.id()); it != active_.end()) return it->second;
    if (stopping_ || stored.state() != v1::RUNNING || stored.replica() != replica_.id) {
      return nullptr;
    }
    claimed_.wait_for(lock, kRecheck);
    if (auto it = active_.find(stored.id()); it != active_.end()) return it->second;
    lock.unlock();
    std::optional<v1::RunInfo> again = store_->GetRun(stored.id());
    lock.lock();
    if (!again) return nullptr;
    stored = std::move(*again);
  }
}

void RunQueue::Drain(std::chrono::duration<double> grace) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    draining_ = true;
  }
  work_.notify_all();
  UpdateServing();
  spdlog::info("replica {} draining: no more claims, up to {} s for the runs integrating here",
               replica_.id, grace.count());
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait_for(lock, grace, [&] { return active_.size() == queue_.size(); });
}

std::optional<std::string> RunQueue::stop_reason() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!stopping_) return std::nullopt;
  return stop_reason_;
}

bool RunQueue::Shutdown(const std::string& reason) {
  std::deque<std::shared_ptr<Run>> queued;
  std::map<std::string, std::shared_ptr<Run>> elsewhere;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_ && workers_.empty() && !keeper_.joinable()) return false;
    stopping_ = true;
    stop_reason_ = reason;
    queued.swap(queue_);
    elsewhere.swap(elsewhere_);
    for (const auto& run : queued) active_.erase(run->id());
    for (auto& [id, run] : active_) {
      run->interrupted = true;
      run->cancel = true;
    }
  }
  work_.notify_all();
  claimed_.notify_all();
  hooks_.state_changed();  // AwaitChange returns
  for (std::thread& worker : workers_) worker.join();
  workers_.clear();
  EndLeftRuns(queued, elsewhere, reason);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    keeper_stop_ = true;
  }
  keeper_wake_.notify_all();
  if (keeper_.joinable()) keeper_.join();
  UpdateServing();
  return true;
}

void RunQueue::EndLeftRuns(const std::deque<std::shared_ptr<Run>>& queued,
                           const std::map<std::string, std::shared_ptr<Run>>& elsewhere,
                           const std::string& reason) {
  // Runs queued here and not claimed: INTERRUPTED with a private store (but those of the
  // sweeps it feeds); left queued in a shared one (another replica takes them).
  std::map<std::string, bool> fed_sweeps;  // by id: stored and not cancelled
  auto fed = [&](const std::string& sweep_id) {
    if (sweep_id.empty()) return false;
    auto [known, inserted] = fed_sweeps.try_emplace(sweep_id, false);
    if (inserted) {
      try {
        const std::optional<StoredSweep> sweep = store_->GetSweep(sweep_id, false);
        known->second = sweep && !sweep->cancelled;
      } catch (const std::exception& error) {
        spdlog::error("sweep {}: reading it failed: {}", sweep_id, error.what());
      }
    }
    return known->second;
  };
  for (const auto& run : queued) {
    std::optional<v1::RunInfo> ended;
    // A run of a sweep the server feeds stays queued: the next start runs it.
    if (replica_.private_store && !fed(run->Info().sweep_id())) {
      try {
        ended = store_->EndQueuedRun(run->id(), v1::INTERRUPTED,
                                     reason + " before this run started", NowMs());
      } catch (const std::exception& error) {
        spdlog::error("run {}: storing its interruption failed: {}", run->id(), error.what());
      }
    }
    EndPlaceholder(run, ended ? *ended : run->Info());
  }
  for (const auto& [id, run] : elsewhere) run->End();
}

}  // namespace mbstream
