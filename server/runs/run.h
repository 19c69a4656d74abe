// One run on the server: its constant request, its live state and its fan-out channel.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/run.pb.h"
#include "server/runs/control_channel.h"
#include "server/runs/frame_spool.h"
#include "server/runs/model_registry.h"
#include "server/runs/probe_recorder.h"
#include "server/runs/run_clock.h"
#include "server/runs/subscription.h"
#include "server/sim/run_config.h"

namespace mbstream {

class Run {
 public:
  // `clock` (which must outlive the run) times the probe recorder's batches.
  Run(const v1::RunInfo& info, const RunConfig& config, std::shared_ptr<const CompiledModel> model,
      const RunClock& clock = SteadyRunClock(), ProbeRecorder::Options probe_options = {});

  const std::string& id() const { return id_; }
  const CompiledModel& model() const { return *model_; }
  std::shared_ptr<const CompiledModel> shared_model() const { return model_; }
  const RunConfig& config() const { return config_; }
  double realtime() const { return realtime_; }

  // A snapshot of the run's info with live counters (frames, t, subscribers, probes).
  v1::RunInfo Info() const;
  v1::RunState state() const;  // Info().state() without the copy
  // Changes the info under the run's lock.
  template <typename Change>
  void UpdateInfo(Change change) {
    std::lock_guard<std::mutex> lock(mutex_);
    change(info_);
  }

  // Fan-out. Attach sends the run-started event (if asked), then the latest frame, then
  // every later frame; a subscriber attached after the run ended gets only the run-ended
  // event. Attaching a subscriber that is attached already does nothing. Publish keeps the
  // frame as the latest (only that one: the result is in the store, see spool()) and pushes
  // it to every subscriber. It swaps `frame` in: `frame` gets the previous latest frame's
  // storage back, for the caller to fill again, so that a run nobody subscribes to allocates
  // nothing per frame (subscribers get one shared copy of each frame).
  void Attach(const std::shared_ptr<Subscription>& subscriber, bool send_started);
  void Publish(v1::Frame* frame);
  // Marks the run ended: pushes the run-ended event and detaches every subscriber.
  void End();
  bool ended() const;
  int subscriber_count() const;
  std::shared_ptr<const v1::Frame> latest_frame() const;  // a copy; nullptr before the first

  // The frames on their way to the store; the run's worker thread only.
  FrameSpool& spool() { return spool_; }

  // The viewers' probe reports on their way to the store (probe_recorder.h): the run's
  // worker opens it with the run's store writer and stores a batch when one is due; Finish
  // closes it and stores the last batch.
  ProbeRecorder& probes() { return probes_; }
  // Waits up to `timeout` until a probe report for frame `seq` or later arrived, when a
  // viewer (a Subscribe stream) has attached to this run. Returns at once otherwise.
  void WaitForProbes(int64_t seq, std::chrono::duration<double> timeout);

  // The channel to the run's controller (control_channel.h): a run with external drives has
  // one, made with the run; null otherwise.
  const std::shared_ptr<ControlChannel>& control() const { return control_; }

  std::atomic<bool> cancel{false};       // CancelRun or shutdown: stop the integration
  std::atomic<bool> interrupted{false};  // the server is shutting down
  // The store shows this replica's lease on the run taken over (it was reaped after the
  // lease expired): the run stops and stores nothing more (docs/cluster.md).
  std::atomic<bool> lease_lost{false};

 private:
  const std::string id_;
  const std::shared_ptr<const CompiledModel> model_;
  const RunConfig config_;
  const double realtime_;

  mutable std::mutex mutex_;
  v1::RunInfo info_;
  v1::Frame latest_frame_;  // what a late subscriber gets first (when published_ > 0)
  int64_t published_ = 0;   // frames published
  FrameSpool spool_;        // the run's thread only, no lock
  ProbeRecorder probes_;    // thread-safe itself
  std::vector<std::shared_ptr<Subscription>> subscribers_;
  int viewers_ = 0;  // Subscribe streams ever attached
  bool ended_ = false;
  std::shared_ptr<ControlChannel> control_;  // after `cancel`, which it reads
};

}  // namespace mbstream
