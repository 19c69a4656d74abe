// Runs on the server: a facade over parts that own their state and are tested alone:
// RunQueue (the queue, the worker threads, leases, cluster claims, draining and shutdown),
// FanOut (subscriptions, followers, announcements), FollowerReplays (stored runs replayed to
// the followers) and each run's ProbeRecorder (probe reports stored in batches as they come;
// a replay's from RecordProbeSet). It validates and prepares runs, integrates a claimed run
// (run_execution.cc) and answers reads. gRPC-free: the service calls it.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mbstream/v1/replay.pb.h"
#include "mbstream/v1/run.pb.h"
#include "mbstream/v1/run_spec.pb.h"
#include "mbstream/v1/sweep.pb.h"
#include "server/runs/fan_out.h"
#include "server/runs/follower_replays.h"
#include "server/runs/free_space.h"
#include "server/runs/model_registry.h"
#include "server/runs/pending_finals.h"
#include "server/runs/probe_recorder.h"
#include "server/runs/recent_results.h"
#include "server/runs/replay_cursor.h"
#include "server/runs/run.h"
#include "server/runs/run_clock.h"
#include "server/runs/run_queue.h"
#include "server/runs/server_limits.h"
#include "server/runs/subscription.h"
#include "server/runs/sweep_feeder.h"
#include "server/runs/sweep_plan.h"
#include "server/store/run_lease.h"
#include "server/store/stored_sweep.h"

namespace mbstream {

class Store;
class ClusterFollow;

class RunManager {
 public:
  // `models`, `store` and `clock` are not owned and must outlive the manager (`clock` paces
  // realtime runs; the steady clock when null). Starts the run queue (run_queue.h): with a
  // private store, runs the store still lists as queued or running (a previous server died)
  // are marked INTERRUPTED; then `limits.workers` worker threads and the lease keeper start.
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
  // Sweeps the server feeds (run_manager_sweep.cc; docs/cluster.md, "Sweeps"). StartSweep
  // checks every point's values against the spec's fields and the first `window` points
  // against the model (InputError or RequestError naming the point), stores the sweep whole
  // and queues its first window (as the queue has room); the feeder queues the rest, at most
  // `window` (0: 32) of its runs queued or running at once. A later point the model refuses
  // is stored as a FAILED run of the sweep. Throws as StartMany.
  struct StartedSweep {
    std::string id;
    int total_points = 0;
    std::vector<std::string> paths;
    std::vector<v1::RunInfo> runs;  // queued (or FAILED) by this call, in point order
    std::vector<std::vector<std::string>> values;  // each run's values, in paths' order
  };
  StartedSweep StartSweep(const std::string& model, v1::SweepDefinition definition, int window,
                          const std::string& owner);
  // A sweep as the store holds it: its row (nullopt for a sweep an older server started in
  // slices: then `runs` are all its runs), its runs by state (those integrating here as they
  // are now) and a page of its runs, in point order from point `runs_from`, at most
  // `max_runs` (0 = 1,000, at most 1,000), each with its values. Throws kNotFound.
  struct SweepView {
    std::optional<StoredSweep> stored;
    std::map<int, int> states;  // by v1::RunState
    std::vector<v1::RunInfo> runs;
    std::vector<std::string> paths;
    std::vector<std::vector<std::string>> values;  // of each run of `runs` (with `stored`)
  };
  SweepView ViewSweep(const std::string& sweep_id, int runs_from, int max_runs) const;
  // The runs of sweep `sweep_id` QUEUED or RUNNING in the store (at most its window).
  std::vector<v1::RunInfo> UnfinishedSweepRuns(const std::string& sweep_id) const;
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
  // A Control stream attaches to run `run_id` (run_manager_control.cc): a run queued or
  // integrating here with external drives and no controller yet, started by `caller` (or
  // any run for an admin). Returns its channel, its info and the run's joints; `denied` says
  // why not when the caller may not (another token's run, or controlled by another stream
  // already: PERMISSION_DENIED). Throws RequestError: kNotFound, kFailedPrecondition (ended,
  // elsewhere, no external drives).
  struct ControlAttachment {
    std::shared_ptr<ControlChannel> channel;  // null when denied
    std::string denied;
    v1::RunInfo info;
    std::vector<std::string> joint_names, external_joints, commands;
    double period_s = 0.0;
  };
  ControlAttachment AttachControl(const std::string& run_id, const std::string& caller, bool admin);
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
  void ForgetEnded(const std::string& run_id) {
    recent_results_.Erase(run_id);
    pending_finals_.Erase(run_id);
  }
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

  // This replica (RunQueue). Its id; the address it advertises (set once the
  // server listens); whether it should get calls: the store answered the keeper's last look
  // and it is neither draining nor stopping. `listener` is called with each change of that
  // (from the keeper's thread or Drain's caller), and at once with the present value.
  const std::string& replica_id() const { return replica_.id; }
  void SetAdvertisedAddress(const std::string& address) { queue_.SetAdvertisedAddress(address); }
  bool serving() const { return queue_.serving(); }
  void SetServingListener(std::function<void(bool)> listener) {
    queue_.SetServingListener(std::move(listener));
  }

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
  // What the run queue asks of the manager (RunQueue::Hooks).
  RunQueue::Hooks QueueHooks();
  // A claimed run, on a worker thread: executed (a failure becomes the outcome), finished.
  void RunClaimed(const std::shared_ptr<Run>& run);
  std::shared_ptr<Run> RunOf(const v1::RunInfo& info);  // model compiled, config prepared
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
  // A run queued or integrating here (RunQueue::Find); nullptr otherwise.
  std::shared_ptr<Run> FindActive(const std::string& run_id) const { return queue_.Find(run_id); }
  // False when no run of this replica is running (the follower waits for the next).
  bool AttachLocalFollow(const std::shared_ptr<Subscription>& subscriber);
  // A new run id: the time and 32 random bits (free in the store only once AddRuns took it).
  std::string NewRunId() const;
  // How runs and replays batch their probe reports: limits_.max_probe_reports, a batch at
  // least every limits_.frame_flush_s (as frames).
  ProbeRecorder::Options ProbeOptions() const;
  // StartMany's first step (run_manager.cc): every spec checked and its info filled (errors
  // name the spec).
  std::vector<RunConfig> PrepareRuns(const CompiledModel& model,
                                     const google::protobuf::RepeatedPtrField<v1::RunSpec>& specs,
                                     const std::string& owner, std::vector<v1::RunInfo>& infos);
  // A run of this replica changed state (AwaitChange): counted and notified.
  void NoteStateChange();
  // The feeder's step (run_manager_sweep.cc): points [first, first + count) of `sweep` (at
  // most what the queue takes) expanded, checked and stored with the sweep's next point in
  // one store transaction, the QUEUED ones queued here. Returns the runs stored, in point
  // order; none when the store refused them (another replica queued them first, the sweep
  // was cancelled or its window is full), the queue is full or stopping, or the disk full.
  std::vector<v1::RunInfo> FeedSweep(const StoredSweep& sweep, const SweepPlan& plan, int first,
                                     int count);

  ModelRegistry* models_;
  Store* store_;
  const ServerLimits limits_;
  RunClock* clock_;

  const ReplicaOptions replica_;      // as given, with its id; the address is RunQueue's
  RecentResults recent_results_;      // frames of ended runs for their GetResult
  PendingFinals pending_finals_;      // final states the store refused (a full disk)
  FanOut fan_out_;                    // subscriptions and follow streams
  FollowerReplays follower_replays_;  // ReplayToFollowers; stopped by Shutdown

  // AwaitChange waits on state_changed_ for state_changes_ to move (NoteStateChange).
  mutable std::mutex changes_mutex_;
  mutable std::condition_variable state_changed_;
  uint64_t state_changes_ = 0;
  std::function<std::string()> run_id_source_;  // SetRunIdSourceForTesting; empty: NewRunId
  FreeSpaceSource free_space_source_;           // SetFreeSpaceSource; empty: no free-space check
  std::string data_dir_;                        // named in the refusal
  // Follow streams of a shared store also get the runs other replicas claim (kRemoteRun).
  std::unique_ptr<ClusterFollow> cluster_follow_;
  // Keeps the stored sweeps' windows filled (FeedSweep); started once queue_ is made, and
  // woken by every state change of this replica's runs.
  SweepFeeder feeder_;
  // Last: its threads call the manager (QueueHooks) as soon as it is made.
  RunQueue queue_;
};

}  // namespace mbstream
