// One WatchRun stream (progress, and optionally frames, of one run until it ends) as a
// reactor on gRPC's callback API: no thread of its own. The service's StreamPump steps it
// at each progress interval, when its subscription has frames (its listener) and every
// kStatePoll for a change of state (sent at once); gRPC's threads complete its writes.
//
// A run queued in a shared store is looked at every 50 ms until a replica claims it; one
// integrating on another replica is watched there, its owner's events relayed unchanged
// (peer_proxy.h; one thread for the owner's blocking client stream). With frames, the
// stream ends only after the subscription's run-ended event, which comes after the run's
// last frame: every frame is delivered or counted in a batch's `missed` before the final
// progress event.
#pragma once

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/service/pump_steps.h"
#include "server/service/stream_writes.h"
#include "server/service/subscribe_call.h"

namespace mbstream {

class WatchCall final : public grpc::ServerWriteReactor<v1::WatchEvent>,
                        public Pokeable,
                        public std::enable_shared_from_this<WatchCall> {
 public:
  using Clock = std::chrono::steady_clock;

  static grpc::ServerWriteReactor<v1::WatchEvent>* Open(grpc::CallbackServerContext* context,
                                                        const v1::WatchRunRequest& request,
                                                        const StreamDeps& deps);
  WatchCall(grpc::CallbackServerContext* context, const v1::WatchRunRequest& request,
            const StreamDeps& deps);

  void Poke() override;

  void OnWriteDone(bool ok) override;
  void OnCancel() override;
  void OnDone() override;

 private:
  enum class Phase { kQueued, kWatching, kRelayed, kFinished };

  grpc::Status Begin();  // lock held
  friend class PumpSteps;
  void RunStep();  // a step and a turn (pump_steps.h)
  // With the lock held: runs Pass in this call's turn (pump_steps.h).
  void Turn(std::unique_lock<std::mutex>& lock);
  void Pass(std::unique_lock<std::mutex>& lock);  // Step if asked for, then Drive
  void Step();                                    // lock held, no write pending
  void StepQueued();
  void StepWatching();
  void Watch();  // the run is here (or ended): watched from its subscription
  void Progress(const v1::RunInfo& info);
  void WakeAt(Clock::time_point due);
  bool WriteAndWait(const v1::WatchEvent& event);  // the relay's thread
  // In a turn: starts the next write or finishes the call (lock held; released and taken
  // again around gRPC's calls).
  void Drive(std::unique_lock<std::mutex>& lock);
  void Teardown();

  grpc::CallbackServerContext* const context_;
  const v1::WatchRunRequest request_;
  const StreamDeps deps_;
  std::shared_ptr<WatchCall> self_;  // the reactor's own hold, until OnDone
  LiveStreams::Id live_id_ = 0;

  std::mutex mutex_;
  std::condition_variable written_;  // WriteAndWait's writes completed
  Phase phase_ = Phase::kWatching;
  Clock::duration interval_{};
  Clock::time_point next_progress_;
  v1::RunInfo info_;
  std::shared_ptr<Subscription> slot_;  // counted against the subscriber limit
  std::deque<StreamEvent> events_;
  StreamWrites<v1::WatchEvent> writes_;
  PumpSteps steps_;    // steps and turns
  std::thread relay_;  // started and joined in turns
};

}  // namespace mbstream
