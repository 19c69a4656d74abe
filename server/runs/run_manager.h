// Runs on the server: a bounded queue, a fixed pool of worker threads, cancellation and
// shutdown, and a facade over parts that own their state and are tested alone: FanOut
// (subscriptions, followers, announcements), FollowerReplays (stored runs replayed to the
// followers) and each run's ProbeRecorder (probe reports stored in batches as they come; a
// replay's from RecordProbeSet). gRPC-free: the service calls it.
//
// The queue is in the store (Store::ClaimQueuedRun): Start writes a run QUEUED, and an idle
// worker of any replica on the same store claims the oldest queued run under a lease, which a
// keeper thread renews while the run integrates and which lets the other replicas reap the
// run of a replica that died (run_manager_queue.cc, docs/cluster.md).
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include "mbstream/v1/replay.pb.h"
#include "mbstream/v1/run.pb.h"
#include "mbstream/v1/run_spec.pb.h"
#include "server/runs/fan_out.h"
#include "server/runs/follower_replays.h"
#include "server/runs/free_space.h"
#include "server/runs/model_registry.h"
#include "server/runs/probe_recorder.h"
#include "server/runs/recent_results.h"
#include "server/runs/replay_cursor.h"
#include "server/runs/run.h"
#include "server/runs/run_clock.h"
#include "server/runs/server_limits.h"
#include "server/runs/subscription.h"
#include "server/store/run_lease.h"

namespace mbstream {

class Store;
class ClusterFollow;

// How a run manager takes part in a cluster of replicas sharing one store.
struct ReplicaOptions {
  std::string id;       // RunInfo.replica; empty: host name, process id and a random suffix
  std::string address;  // RunInfo.replica_address (--advertise); may be set later
  // s within which the runs of a replica that died are reaped by another (between half of it
  // and all of it after the death; run_manager_queue.cc, LeaseMs).
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

class RunManager {
 public:
  // `models`, `store` and `clock` are not owned and must outlive the manager (`clock` paces
  // realtime runs; the steady clock when null). With a private store, marks runs the store
  // still lists as queued or running (a previous server died) INTERRUPTED; then starts
  // `limits.workers` threads and the lease keeper.
  RunManager(ModelRegistry* models, Store* store, const ServerLimits& limits,
             RunClock* clock = nullptr, ReplicaOptions replica = {});
  ~RunManager();  // Shutdown("the server stopped")

  // Validates the spec against the model and the limits, queues the run and returns its
  // info (state QUEUED). Throws InputError (bad spec), RequestError (unknown model, limits,
  // queue full, shutting down).
  // `owner` is recorded in the run's info (RunInfo.owner).
  v1::RunInfo Start(const std::string& model, const v1::RunSpec& spec,
                    const std::string& owner = "");
  // Start for several runs of one model at once (a sweep): every spec is validated first
  // (errors name it: "specs[3]: ..."), then either all are queued, stored in one store
  // transaction, or none is (queue too small, store failure, shutting down). Infos in the
  // specs' order. `sweep_id`, if given, is recorded in each (RunInfo.sweep_id), with its
  // point (`first_point` + its index in `specs`) and the sweep's `total_points`.
  std::vector<v1::RunInfo> StartMany(const std::string& model,
                                     const google::protobuf::RepeatedPtrField<v1::RunSpec>& specs,
                                     const std::string& owner = "",
                                     const std::string& sweep_id = "", int first_point = 0,
                                     int total_points = 0);
  // The runs of sweep `sweep_id` the store holds (every replica's), in point order, each as
  // Get returns it (run_manager_sweep.cc). Empty for an unknown sweep.
  std::vector<v1::RunInfo> SweepRuns(const std::string& sweep_id) const;
  // Records on every stored run of sweep `sweep_id` that the sweep was cancelled
  // (RunInfo.sweep_cancelled; Store::MarkSweepCancelled) and returns how many were marked now.
  int MarkSweepCancelled(const std::string& sweep_id);
  // Whether sweep `sweep_id` was cancelled (a stored run carries the mark), from the store's
  // index alone: StartSweep asks before each slice.
  bool SweepCancelled(const std::string& sweep_id) const;
  // Tests only: where new run ids come from (the time and 32 random bits by default), to
  // force the collisions the store refuses. Call before the first Start.
  void SetRunIdSourceForTesting(std::function<std::string()> source) {
    run_id_source_ = std::move(source);
  }
  // Where Start and StartMany learn the free space of the disk of `data_dir` (the SQLite
  // store's data directory), checked against limits().min_free_bytes before any run is
  // queued (free_space.h). Unset (a PostgreSQL store): no check. Call before the first Start.
  void SetFreeSpaceSource(FreeSpaceSource source, std::string data_dir) {
    free_space_source_ = std::move(source);
    data_dir_ = std::move(data_dir);
  }
  // Stops a queued or running run (state CANCELLED with the frames so far); an ended run is
  // returned unchanged. Throws RequestError(kNotFound).
  v1::RunInfo Cancel(const std::string& run_id);
  v1::RunInfo Get(const std::string& run_id) const;  // throws RequestError(kNotFound)
  // Waits until run `run_id`'s state is other than `from`, `until` passes or the manager
  // stops, and returns its info then (run_manager_await.cc). The changes of this replica
  // (claimed, running, ended) wake it at once; those of other replicas sharing the store
  // are seen within 0.1 s. Throws as Get.
  v1::RunInfo AwaitChange(const std::string& run_id, v1::RunState from,
                          std::chrono::steady_clock::time_point until) const;
  // One page of runs, newest first (see ListRunsRequest): at most `page_size` runs
  // (0 = 100, at most 1000) and kMaxPageBytes, of `model`'s runs (all when empty), at most
  // `limit` overall (0 = no limit), after `page_token`. Throws InputError for a bad token.
  struct RunPage {
    std::vector<v1::RunInfo> runs;
    std::string next_page_token;  // empty: no more runs
  };
  static constexpr size_t kMaxPageBytes = 4 << 20;
  RunPage List(const std::string& model, int limit, int page_size,
               const std::string& page_token) const;

  // The stored result of an ended run, read piece by piece (a long run is never in memory
  // at once). ResultInfo throws RequestError: kNotFound, or kFailedPrecondition while the
  // run is queued or running. ResultFrames reads stored chunk `index` (or the next one) into
  // `data` and appends its frames' serialized bytes (views into `data`) to `frames`; it
  // returns the index to ask for next, nullopt after the last (Store::GetSerializedFrames).
  v1::RunInfo ResultInfo(const std::string& run_id) const;
  std::optional<int64_t> ResultFrames(const std::string& run_id, int64_t index, std::string& data,
                                      std::vector<std::string_view>& frames) const;
  std::vector<v1::ProbeReport> ResultProbes(const std::string& run_id) const;
  // Forgets what this replica keeps of ended run `run_id` in memory (RecentResults), after
  // the run was deleted from the store (run_deleter.h): later reads ask the store.
  void ForgetEnded(const std::string& run_id) { recent_results_.Erase(run_id); }
  // Replays (run_manager_replay.cc). Whether the run is queued or running now; a cursor over
  // an ended run's stored frames (`info` from ResultInfo); the replays' probe sets: a new
  // unique set id, creating a set and adding its reports (each call one transaction), the
  // sets of a run (kNotFound for an unknown run) and one set's reports (kNotFound when the
  // set is not one of the run's).
  bool IsActive(const std::string& run_id) const;
  std::unique_ptr<ReplayCursor> OpenReplay(const v1::RunInfo& info) const;
  std::string NewProbeSetId() const;
  // A recorder of a replay's probe reports, opened: probe set `set` is created in the store
  // with its first batch, the reports added in batches as they come (probe_recorder.h).
  std::unique_ptr<ProbeRecorder> RecordProbeSet(const v1::ProbeSet& set) const;
  std::vector<v1::ProbeSet> ListProbeSets(const std::string& run_id) const;
  std::vector<v1::ProbeReport> ResultProbeSet(const std::string& run_id,
                                              const std::string& set_id) const;
  // Streams the ended run `run_id` to the followers attached now (started, its frames paced
  // at `speed_x` simulated s per wall s, ended), as if it were running, on a thread of its
  // own; returns its info at once. Throws ResultInfo's errors, kFailedPrecondition for a run
  // with no frames. Probe reports of a replayed run are refused (it is stored already).
  v1::RunInfo ReplayToFollowers(const std::string& run_id, double speed_x);
  // Hands memory freed after a run or a result back to the system (SQLite's page cache,
  // glibc's arenas: release_memory.h).
  void ReleaseMemory() const;

  // Subscriptions. A subscription counts against limits.max_subscribers from NewSubscription
  // (RESOURCE_EXHAUSTED at the limit) until Unsubscribe, attached to something or not.
  // AttachRun: the run's events (started if `send_started`, latest frame, frames, ended); an
  // ended run gives started + ended at once; NOT_FOUND for an unknown run. AttachFollow:
  // every run that starts from now on, and the one running now (the newest; with a shared
  // store, the newest of the cluster's when none runs here), each with started/frames/ended,
  // each exactly once. SubscribeRun = NewSubscription + AttachRun.
  std::shared_ptr<Subscription> NewSubscription();
  void AttachRun(const std::shared_ptr<Subscription>& subscriber, const std::string& run_id,
                 bool send_started);
  void AttachFollow(const std::shared_ptr<Subscription>& subscriber);
  std::shared_ptr<Subscription> SubscribeRun(const std::string& run_id, bool send_started);
  void Unsubscribe(const std::shared_ptr<Subscription>& subscriber);
  int subscriber_count() const;

  // A viewer's checked probe reports (latency already measured), for its run's probe recorder
  // (stored in batches while the run integrates, the last batch when it ends). False
  // (nothing kept) when the run is not integrating or waiting for its last probes any more,
  // or already holds limits.max_probe_reports reports.
  bool AddProbes(const std::string& run_id, const std::vector<v1::ProbeReport>& reports);

  // Stops accepting runs, interrupts queued and running ones (state INTERRUPTED, frames so
  // far stored; with a shared store, queued runs stay queued and running ones with retries
  // left are queued again), closes every subscription and joins the workers. Idempotent.
  void Shutdown(const std::string& reason);
  // Drains the replica: stops claiming runs, waits up to `grace` for the runs integrating
  // here to end, then Shutdown(reason) (what still runs is handed back).
  void Drain(std::chrono::duration<double> grace, const std::string& reason);

  // This replica (run_manager_queue.cc). Its id; the address it advertises (set once the
  // server listens); whether it should get calls: the store answered the keeper's last look
  // and it is neither draining nor stopping. `listener` is called with each change of that
  // (from the keeper's thread or Drain's caller), and at once with the present value.
  const std::string& replica_id() const { return replica_.id; }
  void SetAdvertisedAddress(const std::string& address);
  bool serving() const;
  void SetServingListener(std::function<void(bool)> listener);

  // The cluster (run_manager_cluster.cc). Where run `run_id` integrates, for the service's
  // proxies: here (with a private store: always, and the store is not read), queued in a
  // shared store (any replica may claim it), on another replica (`info`, from the store,
  // names it: replica, replica_address) or ended. Throws RequestError(kNotFound).
  struct RunPlace {
    enum class Where { kHere, kQueued, kElsewhere, kEnded };
    Where where = Where::kHere;
    v1::RunInfo info;
  };
  RunPlace Locate(const std::string& run_id) const;
  bool shared_store() const { return !replica_.private_store; }
  // Models submitted to other replicas: with a shared store, the store's model list is read
  // again (not compiled: a model is compiled when a run first needs it).
  void RefreshModels() const;
  // A model's info by id or name, reading the store's list again once when it is unknown
  // here (shared store). Throws as ModelRegistry::Info.
  v1::ModelInfo ModelInfo(const std::string& id_or_name) const;

  const ModelRegistry& models() const { return *models_; }
  const ServerLimits& limits() const { return limits_; }

 private:
  // How a run ended, decided by Execute and applied by Finish after storing.
  struct Outcome {
    v1::RunState state = v1::FAILED;
    std::string message;
    v1::RunStats stats;
  };
  void WorkerLoop();
  // The queue (run_manager_queue.cc). Claims the oldest queued run of the store for this
  // replica, with its Run (the one Start made here, or one made from the stored info);
  // nullptr when none is queued or the store failed. With a private store the queue is
  // this process's own: ClaimPrivate takes the oldest stored run of queue_ without a store
  // transaction (its row stays QUEUED until the run ends; a crash marks either INTERRUPTED
  // at the next start).
  std::shared_ptr<Run> ClaimNext();
  std::shared_ptr<Run> ClaimPrivate();
  // Cancels a queued run Cancel took out of a private store's queue_: ended in the store, or
  // (the store failed) queued again with `cancel` set, for a worker to end.
  v1::RunInfo CancelDequeued(const std::shared_ptr<Run>& run);
  std::shared_ptr<Run> RunOf(const v1::RunInfo& info);  // model compiled, config prepared
  RunLease NewLease() const;
  int64_t LeaseMs() const;  // how long a claim or renewal holds
  void KeeperLoop();
  void KeepLeases();  // renews, reaps, follows runs started here and claimed elsewhere
  // Records whether the store answered (when given) and tells the listener of a change.
  void UpdateServing(std::optional<bool> store_reachable = std::nullopt);
  // A run started here ended without a worker of this replica (cancelled while queued,
  // ended elsewhere): shows `info` and ends its streams.
  void EndPlaceholder(const std::shared_ptr<Run>& run, const v1::RunInfo& info);
  // The model by id or name, loading the store's list again once when it is unknown (a
  // model submitted to another replica).
  std::shared_ptr<const CompiledModel> FindModel(const std::string& model_ref) const;
  // The spec checked against the model and turned into the run's config (warnings added).
  RunConfig PrepareConfig(const CompiledModel& model, const v1::RunSpec& spec,
                          std::vector<std::string>* warnings) const;
  Outcome Execute(const std::shared_ptr<Run>& run);
  // Finish's steps (run_execution.cc): the probes' grace, the final info, stored, then shown.
  void Finish(const std::shared_ptr<Run>& run, const Outcome& outcome);
  v1::RunInfo FinalInfo(Run& run, const Outcome& outcome);  // closes the run's probe recorder
  // Stores `info` (the recorder's last batch, the spool's last chunk) unless the lease was
  // lost; then `info` becomes what the store holds.
  void StoreFinal(Run& run, v1::RunInfo& info);
  std::shared_ptr<Run> FindActive(const std::string& run_id) const;
  // A run `stored` says RUNNING here that is not in active_ yet: claimed by a worker of this
  // replica that is still preparing it (ClaimNext). Waits until the worker lists it (the run)
  // or the store shows it otherwise (null: ended, reaped, another replica's).
  std::shared_ptr<Run> AwaitClaimedHere(v1::RunInfo stored);
  // False when no run of this replica is running (the follower waits for the next).
  bool AttachLocalFollow(const std::shared_ptr<Subscription>& subscriber);
  // Throws UNAVAILABLE when stopping, RESOURCE_EXHAUSTED when the queue cannot take `runs`
  // more (mutex_ held).
  void CheckAccepting(int runs = 1) const;
  // A new run id: the time and 32 random bits (free in the store only once AddRuns took it).
  std::string NewRunId() const;
  // How runs and replays batch their probe reports: limits_.max_probe_reports, a batch at
  // least every limits_.frame_flush_s (as frames).
  ProbeRecorder::Options ProbeOptions() const;
  // New ids for `infos` reserved in active_ and queue_ as `runs` (not yet stored), once the
  // queue has room for them all; throws as CheckAccepting. Call without mutex_.
  void ReserveNewRuns(std::vector<v1::RunInfo>& infos, const std::vector<RunConfig>& configs,
                      const std::shared_ptr<const CompiledModel>& model,
                      std::vector<std::shared_ptr<Run>>& runs);
  // StartMany's steps (run_manager.cc): every spec checked and its info filled (errors name
  // the spec); the runs reserved and stored QUEUED (new ids while one is taken); refused
  // when the server began to stop meanwhile; Forget undoes a reservation.
  std::vector<RunConfig> PrepareRuns(const CompiledModel& model,
                                     const google::protobuf::RepeatedPtrField<v1::RunSpec>& specs,
                                     const std::string& owner, std::vector<v1::RunInfo>& infos);
  std::vector<std::shared_ptr<Run>> StoreNewRuns(std::vector<v1::RunInfo>& infos,
                                                 const std::vector<RunConfig>& configs,
                                                 const std::shared_ptr<const CompiledModel>& model);
  void RefuseIfStopped(const std::vector<v1::RunInfo>& infos,
                       const std::vector<std::shared_ptr<Run>>& runs);
  void Forget(const std::vector<std::shared_ptr<Run>>& runs);

  ModelRegistry* models_;
  Store* store_;
  const ServerLimits limits_;
  RunClock* clock_;

  ReplicaOptions replica_;
  RecentResults recent_results_;      // frames of ended runs for their GetResult
  FanOut fan_out_;                    // subscriptions and follow streams
  FollowerReplays follower_replays_;  // ReplayToFollowers; stopped by Shutdown

  mutable std::mutex mutex_;
  std::condition_variable work_;
  uint64_t wakeups_ = 0;  // runs queued by Start or the reaper: idle workers look at the store
  // Runs started here and not yet claimed by any replica (also in active_), oldest first.
  std::deque<std::shared_ptr<Run>> queue_;
  // Runs of queue_ whose QUEUED row Start has not stored yet: not claimable (ClaimPrivate).
  std::set<const Run*> unstored_;
  std::map<std::string, std::shared_ptr<Run>> active_;  // queued here and running here
  // Runs started here that another replica claimed: ended (their streams) when the store
  // shows them ended.
  std::map<std::string, std::shared_ptr<Run>> elsewhere_;
  std::condition_variable idle_;  // a run integrating here ended (Drain waits for it)
  // A claim of this replica was prepared (listed in active_) or failed (AwaitClaimedHere).
  std::condition_variable claimed_;
  // A run of this replica changed state (AwaitChange): counted and notified by
  // NoteStateChange, which is called without mutex_.
  mutable std::condition_variable state_changed_;
  uint64_t state_changes_ = 0;
  void NoteStateChange();
  bool draining_ = false;
  bool store_reachable_ = true;
  bool serving_reported_ = true;  // the last value given to the listener
  std::function<void(bool)> serving_listener_;
  bool keeper_stop_ = false;
  std::condition_variable keeper_wake_;
  std::thread keeper_;
  bool stopping_ = false;
  std::string stop_reason_;
  int run_counter_ = 0;
  std::function<std::string()> run_id_source_;  // SetRunIdSourceForTesting; empty: NewRunId
  FreeSpaceSource free_space_source_;           // SetFreeSpaceSource; empty: no free-space check
  std::string data_dir_;                        // named in the refusal
  std::vector<std::thread> workers_;
  // Follow streams of a shared store also get the runs other replicas claim (kRemoteRun).
  std::unique_ptr<ClusterFollow> cluster_follow_;
};

}  // namespace mbstream
