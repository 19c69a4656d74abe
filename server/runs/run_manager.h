// Runs on the server: a bounded queue, a fixed pool of worker threads, cancellation,
// subscriptions (fan-out), probe reports and shutdown. gRPC-free: the service calls it.
#pragma once

#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "mbstream/v1/run.pb.h"
#include "mbstream/v1/run_spec.pb.h"
#include "server/runs/model_registry.h"
#include "server/runs/run.h"
#include "server/runs/server_limits.h"
#include "server/runs/subscription.h"

namespace mbstream {

class Store;

class RunManager {
 public:
  // `models` and `store` are not owned and must outlive the manager. Marks runs the store
  // still lists as queued or running (a previous server died) INTERRUPTED, then starts
  // `limits.workers` threads.
  RunManager(ModelRegistry* models, Store* store, const ServerLimits& limits);
  ~RunManager();  // Shutdown("the server stopped")

  // Validates the spec against the model and the limits, queues the run and returns its
  // info (state QUEUED). Throws InputError (bad spec), RequestError (unknown model, limits,
  // queue full, shutting down).
  v1::RunInfo Start(const std::string& model, const v1::RunSpec& spec);
  // Stops a queued or running run (state CANCELLED with the frames so far); an ended run is
  // returned unchanged. Throws RequestError(kNotFound).
  v1::RunInfo Cancel(const std::string& run_id);
  v1::RunInfo Get(const std::string& run_id) const;  // throws RequestError(kNotFound)
  std::vector<v1::RunInfo> List(const std::string& model, int limit) const;  // newest first

  // The stored frames and probe reports of an ended run. Throws RequestError: kNotFound,
  // or kFailedPrecondition while the run is queued or running.
  struct StoredResult {
    v1::RunInfo info;
    std::vector<v1::Frame> frames;
    std::vector<v1::ProbeReport> probes;
  };
  StoredResult Result(const std::string& run_id) const;

  // Subscriptions. A subscriber counts against limits.max_subscribers until Unsubscribe.
  // SubscribeRun: the run's events (started if `send_started`, latest frame, frames, ended);
  // an ended run gets started + ended at once. SubscribeFollow: every run that starts from
  // now on, and the one running now (the newest), each with started/frames/ended.
  std::shared_ptr<Subscription> SubscribeRun(const std::string& run_id, bool send_started);
  std::shared_ptr<Subscription> SubscribeFollow();
  void Unsubscribe(const std::shared_ptr<Subscription>& subscriber);
  int subscriber_count() const;

  // A viewer's probe reports (latency already measured); kept with the run, stored with it.
  void AddProbes(const std::string& run_id, const std::vector<v1::ProbeReport>& reports);

  // Stops accepting runs, interrupts queued and running ones (state INTERRUPTED, frames so
  // far stored), closes every subscription and joins the workers. Idempotent.
  void Shutdown(const std::string& reason);

  const ModelRegistry& models() const { return *models_; }

 private:
  // How a run ended, decided by Execute and applied by Finish after storing.
  struct Outcome {
    v1::RunState state = v1::FAILED;
    std::string message;
    v1::RunStats stats;
  };
  void WorkerLoop();
  Outcome Execute(const std::shared_ptr<Run>& run);
  void Finish(const std::shared_ptr<Run>& run, const Outcome& outcome);
  std::shared_ptr<Run> FindActive(const std::string& run_id) const;
  // Counts one more subscriber (mutex_ held), or throws RESOURCE_EXHAUSTED at the limit.
  void CountSubscriber();
  std::string NewRunId();

  ModelRegistry* models_;
  Store* store_;
  const ServerLimits limits_;

  mutable std::mutex mutex_;
  std::condition_variable work_;
  std::deque<std::shared_ptr<Run>> queue_;
  std::map<std::string, std::shared_ptr<Run>> active_;  // queued and running
  std::vector<std::shared_ptr<Subscription>> followers_;
  int subscribers_ = 0;
  bool stopping_ = false;
  std::string stop_reason_;
  int run_counter_ = 0;
  std::vector<std::thread> workers_;
};

}  // namespace mbstream
