// RunQueue's side of the store's run queue (docs/cluster.md): the workers claim queued runs
// under a lease; the keeper thread renews the leases of the runs integrating here, reaps the
// expired leases of dead replicas and follows the runs started here that another replica
// claimed; health (serving).
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "server/runs/run_queue.h"
#include "server/runs/unix_time.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"

namespace mbstream {

namespace {

std::chrono::duration<double> Seconds(double s) { return std::chrono::duration<double>(s); }

}  // namespace

int64_t RunQueue::NowMs() const {
  if (lease_clock_ == nullptr) return NowUnixMs();
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             lease_clock_->Now().time_since_epoch())
      .count();
}

RunLease RunQueue::NewLease() const {
  RunLease lease;
  lease.replica = replica_.id;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    lease.address = replica_.address;
  }
  lease.now_unix_ms = NowMs();
  lease.expires_unix_ms = lease.now_unix_ms + LeaseMs();
  return lease;
}

// Granted for 3/4 of --lease-timeout-s and renewed every 1/4 of it, while every replica's
// keeper looks for expired leases every 1/4 of it: a replica that dies had renewed at most a
// quarter before, its lease expires at most 3/4 later and is seen at most a quarter after
// that, so its runs are marked between 1/2 and 1 lease timeout after its death.
int64_t RunQueue::LeaseMs() const { return static_cast<int64_t>(replica_.lease_timeout_s * 750.0); }

void RunQueue::SetAdvertisedAddress(const std::string& address) {
  std::lock_guard<std::mutex> lock(mutex_);
  replica_.address = address;
}

std::shared_ptr<Run> RunQueue::ClaimPrivate() {
  std::shared_ptr<Run> run;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto next = std::find_if(queue_.begin(), queue_.end(),
                             [&](const auto& r) { return !unstored_.count(r.get()); });
    if (next == queue_.end()) return nullptr;
    run = *next;
    queue_.erase(next);
  }
  RunLease lease = NewLease();
  v1::RunInfo claimed = run->Info();
  ApplyClaim(claimed, lease);
  store_->NoteClaimed(claimed);
  run->UpdateInfo([&](v1::RunInfo& info) {
    info.set_started_unix_ms(claimed.started_unix_ms());
    info.set_replica(claimed.replica());
    info.set_replica_address(claimed.replica_address());
    info.set_attempts(claimed.attempts());
  });
  spdlog::info("run {} claimed by replica {}", run->id(), replica_.id);
  return run;
}

std::shared_ptr<Run> RunQueue::PrepareClaimed(const v1::RunInfo& claimed) {
  std::shared_ptr<Run> run;
  try {
    run = hooks_.prepare(claimed);
  } catch (const std::exception& error) {
    v1::RunInfo failed = claimed;
    failed.set_state(v1::FAILED);
    failed.set_message("replica " + replica_.id + " could not prepare the run: " + error.what());
    failed.set_ended_unix_ms(NowMs());
    spdlog::error("run {}: {}", failed.id(), failed.message());
    try {
      store_->PutRunIfHeld(failed, LeaseHolder(claimed));
    } catch (const std::exception& again) {
      spdlog::error("run {}: storing its failure failed: {}", failed.id(), again.what());
    }
    claimed_.notify_all();  // AwaitClaimedHere reads the store again
    return nullptr;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    active_[run->id()] = run;  // replaces a run of an earlier attempt still finishing
  }
  claimed_.notify_all();
  return run;
}

std::shared_ptr<Run> RunQueue::ClaimNext() {
  if (replica_.private_store) return ClaimPrivate();
  for (;;) {
    std::optional<v1::RunInfo> claimed;
    try {
      claimed = store_->ClaimQueuedRun(NewLease());
    } catch (const std::exception& error) {
      spdlog::error("replica {}: claiming a queued run failed: {}", replica_.id, error.what());
      UpdateServing(false);
      return nullptr;
    }
    if (!claimed) return nullptr;
    std::shared_ptr<Run> run;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto queued = std::find_if(queue_.begin(), queue_.end(),
                                 [&](const auto& r) { return r->id() == claimed->id(); });
      if (queued != queue_.end()) {  // started here
        run = *queued;
        queue_.erase(queued);
      }
    }
    // Else started on another replica, or queued again after its replica died.
    if (!run && !(run = PrepareClaimed(*claimed))) continue;
    run->UpdateInfo([&](v1::RunInfo& info) {  // as the claim stored it
      info.set_started_unix_ms(claimed->started_unix_ms());
      info.set_replica(claimed->replica());
      info.set_replica_address(claimed->replica_address());
      info.set_attempts(claimed->attempts());
      info.set_message(claimed->message());
    });
    spdlog::info("run {} claimed by replica {} (attempt {})", run->id(), replica_.id,
                 claimed->attempts());
    return run;
  }
}

void RunQueue::WorkerLoop() {
  uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      auto woken = [&] { return stopping_ || draining_ || wakeups_ != seen; };
      if (replica_.private_store) {
        work_.wait(lock, woken);
      } else {
        work_.wait_for(lock, Seconds(replica_.claim_poll_s), woken);
      }
      if (stopping_ || draining_) return;
      seen = wakeups_;
    }
    while (std::shared_ptr<Run> run = ClaimNext()) {
      hooks_.execute(run);
      std::lock_guard<std::mutex> lock(mutex_);
      if (stopping_ || draining_) return;
    }
  }
}

void RunQueue::KeeperLoop() {
  const auto period = Seconds(replica_.lease_timeout_s / 4.0);
  std::unique_lock<std::mutex> lock(mutex_);
  while (!keeper_stop_) {
    lock.unlock();
    KeepLeases();
    lock.lock();
    keeper_wake_.wait_for(lock, period, [&] { return keeper_stop_; });
  }
}

void RunQueue::KeepLeases() {
  std::vector<std::shared_ptr<Run>> running, queued, elsewhere;
  // A private store has no leases and no other replica (ClaimPrivate): nothing to renew or
  // follow, only the reap below (which also tells whether the store answers).
  if (!replica_.private_store) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [id, run] : active_) {
      if (std::find(queue_.begin(), queue_.end(), run) == queue_.end()) running.push_back(run);
    }
    queued.assign(queue_.begin(), queue_.end());
    for (const auto& [id, run] : elsewhere_) elsewhere.push_back(run);
  }
  try {
    const int64_t now_ms = NowMs();
    RenewLeases(running, now_ms);
    Reap(now_ms);
    FollowElsewhere(queued, std::move(elsewhere));
    UpdateServing(true);
  } catch (const std::exception& error) {
    spdlog::error("replica {}: the store did not answer the lease keeper: {}", replica_.id,
                  error.what());
    UpdateServing(false);
  }
}

void RunQueue::RenewLeases(const std::vector<std::shared_ptr<Run>>& running, int64_t now_ms) {
  const int64_t expires_ms = now_ms + LeaseMs();
  for (const auto& run : running) {
    const v1::RunInfo info = run->Info();
    if (info.replica().empty() || run->ended() || run->lease_lost) continue;
    if (!store_->RenewLease(run->id(), LeaseHolder(info), expires_ms)) {
      spdlog::warn(
          "run {}: replica {} lost its lease (another replica took the run over); "
          "stopping it here",
          run->id(), replica_.id);
      run->lease_lost = true;
      run->cancel = true;
    }
  }
}

void RunQueue::Reap(int64_t now_ms) {
  bool requeued = false;
  for (const v1::RunInfo& reaped : store_->ReapExpiredLeases(now_ms, replica_.id)) {
    spdlog::warn("run {} reaped by replica {}: {}: {}", reaped.id(), replica_.id,
                 v1::RunState_Name(reaped.state()), reaped.message());
    requeued = requeued || reaped.state() == v1::QUEUED;
  }
  if (requeued) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++wakeups_;
    }
    work_.notify_all();
  }
}

void RunQueue::FollowElsewhere(const std::vector<std::shared_ptr<Run>>& queued,
                               std::vector<std::shared_ptr<Run>> elsewhere) {
  // Runs started here: claimed by another replica (followed until they end there).
  for (const auto& run : queued) {
    std::optional<v1::RunInfo> stored = store_->GetRun(run->id());
    if (!stored || stored->state() == v1::QUEUED || stored->replica() == replica_.id) continue;
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = std::find(queue_.begin(), queue_.end(), run);
    if (it == queue_.end()) continue;
    queue_.erase(it);
    active_.erase(run->id());
    elsewhere_[run->id()] = run;
    elsewhere.push_back(run);
  }
  for (const auto& run : elsewhere) {
    std::optional<v1::RunInfo> stored = store_->GetRun(run->id());
    if (stored && IsFinalState(stored->state())) EndPlaceholder(run, *stored);
  }
}

void RunQueue::UpdateServing(std::optional<bool> store_reachable) {
  std::function<void(bool)> listener;
  bool serving = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (store_reachable) store_reachable_ = *store_reachable;
    serving = store_reachable_ && !draining_ && !stopping_;
    if (serving == serving_reported_) return;
    serving_reported_ = serving;
    listener = serving_listener_;
  }
  spdlog::info("replica {} {}", replica_.id, serving ? "SERVING" : "NOT_SERVING");
  if (listener) listener(serving);
}

bool RunQueue::serving() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return store_reachable_ && !draining_ && !stopping_;
}

void RunQueue::SetServingListener(std::function<void(bool)> listener) {
  bool serving = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    serving_listener_ = listener;
    serving = store_reachable_ && !draining_ && !stopping_;
    serving_reported_ = serving;
  }
  if (listener) listener(serving);
}

}  // namespace mbstream
