// Runs on the server: a facade over parts that own their state and are tested alone:
// RunQueue (the queue, the worker threads, leases, cluster claims, draining and shutdown),
// FanOut (subscriptions, followers, announcements), FollowerReplays (stored runs replayed to
// the followers) and each run's ProbeRecorder (probe reports stored in batches as they come;
// a replay's from RunReplays::RecordProbeSet). It validates and prepares runs, integrates a claimed
// run (run_execution.cc) and answers reads. gRPC-free: the service calls it.
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
#include "server/runs/replica_control.h"
#include "server/runs/run.h"
#include "server/runs/run_clock.h"
#include "server/runs/run_queue.h"
#include "server/runs/run_replays.h"
#include "server/runs/run_results.h"
#include "server/runs/run_subscriptions.h"
#include "server/runs/run_sweeps.h"
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
  // The parts of the facade, each in a header of its own: sweeps the server stores and
  // feeds (run_sweeps.h), stored results read piece by piece (run_results.h), replays and
  // their probe sets (run_replays.h), subscriptions and viewers' probe reports
  // (run_subscriptions.h), and this replica: where runs integrate, the models of other
  // replicas, free space, draining and shutdown (replica_control.h).
  RunSweeps& sweeps() { return sweeps_; }
  const RunSweeps& sweeps() const { return sweeps_; }
  RunResults& results() { return results_; }
  const RunResults& results() const { return results_; }
  RunReplays& replays() { return replays_; }
  const RunReplays& replays() const { return replays_; }
  RunSubscriptions& subscriptions() { return subscriptions_; }
  const RunSubscriptions& subscriptions() const { return subscriptions_; }
  ReplicaControl& replica() { return replica_control_; }
  const ReplicaControl& replica() const { return replica_control_; }

  // Tests only: where new run ids come from (the time and 32 random bits by default), to
  // force the collisions the store refuses. Call before the first Start.
  void SetRunIdSourceForTesting(std::function<std::string()> source) {
    run_id_source_ = std::move(source);
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
    // joint_names: the velocity coordinates' names (coordinate_names.h), position_names the
    // position coordinates'.
    std::vector<std::string> joint_names, position_names, external_joints, commands;
    std::vector<std::string> sensor_names;  // RunConfig::sensor_points' names, in order
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

  const ModelRegistry& models() const { return *models_; }
  const ServerLimits& limits() const { return limits_; }

 private:
  friend class RunSweeps;
  friend class RunResults;
  friend class RunReplays;
  friend class RunSubscriptions;
  friend class ReplicaControl;

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

  ModelRegistry* models_;
  Store* store_;
  const ServerLimits limits_;
  RunClock* clock_;

  const ReplicaOptions replica_;      // as given, with its id; the address is RunQueue's
  RecentResults recent_results_;      // frames of ended runs for their GetResult
  PendingFinals pending_finals_;      // final states the store refused (a full disk)
  FanOut fan_out_;                    // subscriptions and follow streams
  FollowerReplays follower_replays_;  // RunReplays::ToFollowers; stopped by Shutdown

  // AwaitChange waits on state_changed_ for state_changes_ to move (NoteStateChange).
  mutable std::mutex changes_mutex_;
  mutable std::condition_variable state_changed_;
  uint64_t state_changes_ = 0;
  std::function<std::string()> run_id_source_;  // SetRunIdSourceForTesting; empty: NewRunId
  FreeSpaceSource free_space_source_;  // ReplicaControl::SetFreeSpaceSource; empty: no check
  std::string data_dir_;               // named in the refusal
  // The facade's parts: views of this manager (each holds a reference to it only).
  RunSweeps sweeps_{*this};
  RunResults results_{*this};
  RunReplays replays_{*this};
  RunSubscriptions subscriptions_{*this};
  ReplicaControl replica_control_{*this};
  // Follow streams of a shared store also get the runs other replicas claim (kRemoteRun).
  std::unique_ptr<ClusterFollow> cluster_follow_;
  // Keeps the stored sweeps' windows filled (FeedSweep); started once queue_ is made, and
  // woken by every state change of this replica's runs.
  SweepFeeder feeder_;
  // Last: its threads call the manager (QueueHooks) as soon as it is made.
  RunQueue queue_;
};

}  // namespace mbstream
