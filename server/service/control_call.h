// One Control stream (proto/mbstream/v1/control.proto: a controller in the loop of a run,
// lockstep) as a reactor on gRPC's callback API. Its start (the run started or found, the
// channel attached: may block on a model's compilation) runs on a thread of its own; then it
// has none: gRPC's thread that reads a command checks it and hands it to the run's
// ControlChannel (server/runs/control_channel.h), which wakes the run's worker; the worker
// hands the next state to this call (ControlWriter::Write), which starts its write on the
// worker's thread. So a round trip crosses one thread hand-off beyond a bare echo, where the
// synchronous API's reader and writer threads crossed three (docs/performance.md).
//
// The stream ends after `ended` (the run's final info) once the client half-closes, or at
// once with the status of a command refused (the run failed with it), or CANCELLED. A client
// that does not read while more than kMaxQueued states wait to be written is cancelled.
#pragma once

#include <grpcpp/grpcpp.h>

#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/runs/control_channel.h"
#include "server/runs/run_manager.h"
#include "server/service/subscribe_call.h"

namespace mbstream {

class ControlCall final : public grpc::ServerBidiReactor<v1::ControlRequest, v1::ControlResponse>,
                          public ControlWriter,
                          public Pokeable,
                          public std::enable_shared_from_this<ControlCall> {
 public:
  // Messages queued for a client that does not read before its call is cancelled.
  static constexpr size_t kMaxQueued = 4096;

  // The reactor of a new call (gRPC holds it until OnDone).
  static grpc::ServerBidiReactor<v1::ControlRequest, v1::ControlResponse>* Open(
      grpc::CallbackServerContext* context, const StreamDeps& deps);
  ControlCall(grpc::CallbackServerContext* context, const StreamDeps& deps);

  // ControlWriter: from the run's worker (and the channel), never blocking.
  bool Write(const v1::ControlResponse& response) override;
  void Ended() override;

  // The server stops (LiveStreams): the call is cancelled.
  void Poke() override;

  // gRPC's reactions.
  void OnReadDone(bool ok) override;
  void OnWriteDone(bool ok) override;
  void OnCancel() override;
  void OnDone() override;

 private:
  void Start();                        // the starter thread's body
  grpc::Status Attach();               // Start's part that may throw
  void HandleCommand();                // request_ holds a command (lock held)
  void WatchRun();                     // every 250 ms: a run that ended without Ended
  void Conclude(const grpc::Status&);  // the first status given stays (lock held)
  // TryCancel unless the call is finishing (lock held; released around it): from threads of
  // our own (the server's stop, the worker), which no gRPC reaction holds the call for.
  void Cancel(std::unique_lock<std::mutex>& lock);
  // Starts the next write, a read that is due, or finishes the call (lock held; released
  // around gRPC's calls, which may run a reaction inline; released for good when it finishes
  // the call, whose Finish runs on the pump).
  void Drive(std::unique_lock<std::mutex>& lock);

  grpc::CallbackServerContext* const context_;
  const StreamDeps deps_;
  std::shared_ptr<ControlCall> self_;  // the reactor's own hold, until OnDone
  LiveStreams::Id live_id_ = 0;
  std::thread starter_;  // Start; joined in OnDone

  std::mutex mutex_;
  v1::ControlRequest request_;  // the read in flight
  RunManager::ControlAttachment attachment_;
  std::shared_ptr<ControlChannel> channel_;  // once attached
  std::string run_id_;
  std::deque<v1::ControlResponse> queue_;  // to write; the front is being written if writing_
  bool writing_ = false;
  bool start_read_ = false;    // the start message came
  bool starting_ = false;      // the starter thread runs Start
  bool reading_ = false;       // a read is in flight
  bool read_wanted_ = false;   // a read is to be started (Drive)
  bool reads_done_ = false;    // the client half-closed (or went away)
  bool ended_queued_ = false;  // `ended` was queued (written when queue_ is empty)
  bool broken_ = false;        // a write failed or the call was cancelled
  int outside_ = 0;            // gRPC calls under way without the lock (no Finish meanwhile)
  bool finished_ = false;      // Finish was called
  std::optional<grpc::Status> conclusion_;  // the status to end with, once the run's end is sent
};

}  // namespace mbstream
