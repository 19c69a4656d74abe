// The run queue of one replica (docs/cluster.md): the runs started here and not yet claimed,
// the runs integrating here, a fixed pool of worker threads that claim queued runs, and the
// keeper thread that renews the leases of the runs integrating here, reaps the expired leases
// of dead replicas and follows the runs started here that another replica claimed; health
// (serving), draining and shutdown. Part of RunManager (its facade, run_manager.h), which
// tells it how to prepare, integrate and show a run (Hooks). Thread-safe.
//
// The queue is in the store (Store::ClaimQueuedRun): Enqueue writes runs QUEUED, and an idle
// worker of any replica on the same store claims the oldest queued run under a lease. With a
// private store (SQLite) the queue is this process's own: a worker takes the oldest run of the
// in-memory queue without a store transaction (its row stays QUEUED until the run ends).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "mbstream/v1/run.pb.h"
#include "server/runs/run.h"
#include "server/runs/run_clock.h"
#include "server/runs/server_limits.h"
#include "server/runs/subscription.h"
#include "server/store/run_lease.h"

namespace mbstream {

class Store;

// How a run manager takes part in a cluster of replicas sharing one store.
struct ReplicaOptions {
  std::string id;       // RunInfo.replica; empty: host name, process id and a random suffix
  std::string address;  // RunInfo.replica_address (--advertise); may be set later
  // s within which the runs of a replica that died are reaped by another (between half of it
  // and all of it after the death; run_queue_leases.cc, LeaseMs).
  double lease_timeout_s = 10.0;
  // s between looks at the shared store's queue by an idle worker (runs started on other
  // replicas); a private store is looked at only when this replica queues a run.
  double claim_poll_s = 0.25;
  // A store of this server alone (SQLite): runs it left queued or running are INTERRUPTED at
  // start, and queued ones when it stops. A shared store (PostgreSQL): they stay for the
  // other replicas and the lease reaper, and interrupted runs with retries left are queued
  // again.
  bool private_store = true;
};

class RunQueue {
 public:
  // What the queue asks of its owner. Each is called without the queue's lock held.
  struct Hooks {
    std::function<std::string()> new_run_id;  // a fresh id for a run Enqueue stores
    // The Run of a run claimed here that was started elsewhere (or queued again after its
    // replica died): model compiled, config prepared. Throws when it cannot be prepared (the
    // run is stored FAILED).
    std::function<std::shared_ptr<Run>(const v1::RunInfo&)> prepare;
    // Integrates a claimed run on a worker thread, stores it, calls Release and ends it.
    std::function<void(const std::shared_ptr<Run>&)> execute;
    std::function<void()> state_changed;  // a run of this replica changed state
  };

  // `store` is not owned and must outlive the queue. `replica.id` must be set. With a
  // private store, marks runs the store still lists as queued or running (a previous server
  // died) INTERRUPTED, but queues those of the sweeps it feeds again (RequeueSweepRuns);
  // then starts `limits.workers` worker threads and the keeper. Lease
  // times (claims, renewals, reaps) are the milliseconds of `lease_clock` since its epoch
  // (a test's manual clock); Unix time, as every replica sharing the store, when null.
  RunQueue(Store* store, ReplicaOptions replica, const ServerLimits& limits, Hooks hooks,
           const RunClock* lease_clock = nullptr);
  ~RunQueue();  // Shutdown("the server stopped")

  // Queues new runs `infos` (QUEUED, each given a new id; made into Runs by `make_run`, its
  // index in `infos`): reserved here, stored in one store transaction (new ids for all while
  // the store holds one already) and the workers woken. Returns the runs in `infos`' order.
  // Throws RequestError: kUnavailable when stopping or draining, kResourceExhausted when the
  // queue (limits.max_queued_runs) has no room for them all; the store's errors.
  // `store_runs`, when given, stores them instead of Store::AddRuns (a sweep's points:
  // Store::AddSweepRuns), with AddRuns' contract: false when an id is taken; what it throws
  // leaves nothing queued.
  using StoreRuns = std::function<bool(const std::vector<v1::RunInfo>&)>;
  std::vector<std::shared_ptr<Run>> Enqueue(
      std::vector<v1::RunInfo>& infos,
      const std::function<std::shared_ptr<Run>(const v1::RunInfo&, size_t)>& make_run,
      const StoreRuns& store_runs = nullptr);
  // How many more runs the queue takes now (limits.max_queued_runs less those queued here).
  int Room() const;
  // Cancels a run queued or integrating here, or queued in the store by any replica: its info
  // (CANCELLED when it was queued; cancel requested when it integrates here). nullopt when
  // the run is neither (ended, unknown, or integrating on another replica).
  std::optional<v1::RunInfo> Cancel(const std::string& run_id);
  // A run queued here or integrating here; nullptr otherwise.
  std::shared_ptr<Run> Find(const std::string& run_id) const;
  // Whether run `run_id` is integrating here (claimed, not queued).
  bool IntegratesHere(const std::string& run_id) const;
  // The infos of the runs of sweep `sweep_id` queued or integrating here.
  std::vector<v1::RunInfo> SweepInfos(const std::string& sweep_id) const;
  // The newest run integrating here in state RUNNING, or nullptr.
  std::shared_ptr<Run> NewestRunning() const;
  // Run `run` (claimed here) is stored and about to end: no longer listed (Find), and
  // Drain looks again whether any run integrates here.
  void Release(const std::shared_ptr<Run>& run);

  // Attaches `subscriber` to run `run_id` (Run::Attach) when it is queued or integrating
  // here, started here and followed on another replica, or claimed here a moment ago and
  // still being prepared by a worker (waits for it). kNotFound: the store has no such run;
  // kNotHere: ended, or integrating on another replica (nothing attached).
  enum class Attached { kAttached, kNotFound, kNotHere };
  Attached Attach(const std::shared_ptr<Subscription>& subscriber, const std::string& run_id,
                  bool send_started);

  // One round of the keeper, which runs one every lease_timeout_s / 4: renews the leases of
  // the runs integrating here (a run whose lease another replica took is cancelled), reaps
  // the expired leases of any replica (runs queued again wake the workers), follows the runs
  // started here that another replica claimed until they end, and records whether the store
  // answered (serving).
  void KeepLeases();
  // A lease of this replica from now (lease_clock), for 3/4 of lease_timeout_s.
  RunLease NewLease() const;
  void SetAdvertisedAddress(const std::string& address);

  // The store answered the keeper's last look and the queue is neither draining nor
  // stopping. `listener` is called with each change of that (from the keeper's thread or
  // Drain's and Shutdown's callers), and at once with the present value.
  bool serving() const;
  void SetServingListener(std::function<void(bool)> listener);
  // Stops claiming runs and waits up to `grace` for the runs integrating here to end (the
  // caller then shuts the queue down, which hands back what still runs).
  void Drain(std::chrono::duration<double> grace);
  // Stops accepting runs; the runs integrating here are cancelled and marked interrupted;
  // the workers are joined; the runs queued here end (INTERRUPTED in a private store,
  // left QUEUED in a shared one) as the runs started here and followed elsewhere; then the
  // keeper is joined. False (nothing done) when it was shut down already.
  bool Shutdown(const std::string& reason);
  // Shutdown's reason once it began; nullopt before.
  std::optional<std::string> stop_reason() const;

 private:
  // At start with a private store: the runs of stored sweeps a previous server left queued
  // or running (Store::ListUnfinishedSweepRuns) queued here again under their ids, from their
  // start; one queued again kMaxSweepRestarts times already ends INTERRUPTED instead.
  void RequeueSweepRuns();
  void WorkerLoop();
  void KeeperLoop();
  std::shared_ptr<Run> ClaimNext();
  std::shared_ptr<Run> ClaimPrivate();
  // A run claimed from the shared store that was started elsewhere: prepared and listed, or
  // stored FAILED (nullptr).
  std::shared_ptr<Run> PrepareClaimed(const v1::RunInfo& claimed);
  int64_t NowMs() const;    // lease_clock_'s milliseconds, or Unix time
  int64_t LeaseMs() const;  // how long a claim or renewal holds
  // KeepLeases' steps: renewals (a lost lease cancels the run); the reaper; runs started here
  // and claimed elsewhere, followed until they end there.
  void RenewLeases(const std::vector<std::shared_ptr<Run>>& running, int64_t now_ms);
  void Reap(int64_t now_ms);
  void FollowElsewhere(const std::vector<std::shared_ptr<Run>>& queued,
                       std::vector<std::shared_ptr<Run>> elsewhere);
  // Records whether the store answered (when given) and tells the listener of a change.
  void UpdateServing(std::optional<bool> store_reachable = std::nullopt);
  // A run started here ended without a worker of this replica (cancelled while queued,
  // ended elsewhere): shows `info` and ends its streams.
  void EndPlaceholder(const std::shared_ptr<Run>& run, const v1::RunInfo& info);
  // Cancels a queued run Cancel took out of a private store's queue_: ended in the store, or
  // (the store failed) queued again with `cancel` set, for a worker to end.
  v1::RunInfo CancelDequeued(const std::shared_ptr<Run>& run);
  // A run the store shows RUNNING here that is not in active_ yet: claimed by a worker of
  // this replica that is still preparing it (ClaimNext). Waits until the worker lists it (the
  // run) or the store shows it otherwise (null: ended, reaped, another replica's).
  std::shared_ptr<Run> AwaitClaimedHere(v1::RunInfo stored);
  // Enqueue's steps: new ids reserved in active_ and queue_ (not claimable until stored),
  // once the queue has room (throws as CheckAccepting); undone by Forget; once stored, made
  // claimable, or refused when the queue began to stop meanwhile.
  std::vector<std::shared_ptr<Run>> Reserve(
      std::vector<v1::RunInfo>& infos,
      const std::function<std::shared_ptr<Run>(const v1::RunInfo&, size_t)>& make_run);
  void Forget(const std::vector<std::shared_ptr<Run>>& runs);
  void MakeClaimable(const std::vector<v1::RunInfo>& infos,
                     const std::vector<std::shared_ptr<Run>>& runs);
  // Throws UNAVAILABLE when stopping or draining, RESOURCE_EXHAUSTED when the queue cannot
  // take `runs` more (mutex_ held).
  void CheckAccepting(int runs) const;
  // The runs Shutdown took out: queued here (ended as Shutdown says) and followed elsewhere.
  void EndLeftRuns(const std::deque<std::shared_ptr<Run>>& queued,
                   const std::map<std::string, std::shared_ptr<Run>>& elsewhere,
                   const std::string& reason);

  Store* store_;
  const int workers_count_;
  const int max_queued_runs_;
  const Hooks hooks_;
  const RunClock* lease_clock_;

  mutable std::mutex mutex_;
  ReplicaOptions replica_;  // address under mutex_
  std::condition_variable work_;
  uint64_t wakeups_ = 0;  // runs queued by Enqueue or the reaper: idle workers look at the store
  // Runs started here and not yet claimed by any replica (also in active_), oldest first.
  std::deque<std::shared_ptr<Run>> queue_;
  // Runs of queue_ whose QUEUED row Enqueue has not stored yet: not claimable (ClaimPrivate).
  std::set<const Run*> unstored_;
  std::map<std::string, std::shared_ptr<Run>> active_;  // queued here and running here
  // Runs started here that another replica claimed: ended (their streams) when the store
  // shows them ended.
  std::map<std::string, std::shared_ptr<Run>> elsewhere_;
  std::condition_variable idle_;  // a run integrating here ended (Drain waits for it)
  // A claim of this replica was prepared (listed in active_) or failed (AwaitClaimedHere).
  std::condition_variable claimed_;
  bool draining_ = false;
  bool store_reachable_ = true;
  bool serving_reported_ = true;  // the last value given to the listener
  std::function<void(bool)> serving_listener_;
  bool keeper_stop_ = false;
  std::condition_variable keeper_wake_;
  bool stopping_ = false;
  std::string stop_reason_;
  std::vector<std::thread> workers_;
  std::thread keeper_;
};

}  // namespace mbstream
