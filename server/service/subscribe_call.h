// One Subscribe stream (the viewers' stream) as a reactor on gRPC's callback API: no thread of
// its own. gRPC's threads deliver its reads (the `start` message, then probe reports, which
// are checked against the frames sent and stored at once) and its write completions; the
// service's StreamPump runs its sender when there is something to send (a subscription's
// listener, a replay's timer, a control) and its deadlines. What it sends depends on the
// kind of stream the start asks for, one sender each (subscribe_senders.h): live (one run
// integrating here), follow (every run), replay (a stored run, paced) and relay (a run
// integrating on another replica, its owner's stream passed on).
//
// A stream counts against the subscriber limit from its first moment; one that sends no
// `start` within the limit's deadline is ended. A one-run stream ends OK after run_ended
// once the viewer half-closes (its last probe reports come before; at most 10 s are waited
// for), a stream ended by the server (`closing`) likewise within 2 s; otherwise the call is
// cancelled.
#pragma once

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/runs/model_registry.h"
#include "server/runs/run_manager.h"
#include "server/service/authorizer.h"
#include "server/service/live_streams.h"
#include "server/service/peer_channels.h"
#include "server/service/pump_steps.h"
#include "server/service/replay_inbox.h"
#include "server/service/sent_frames.h"
#include "server/service/stream_pump.h"
#include "server/service/stream_writes.h"

namespace mbstream {

// The service's parts a stream uses; none is owned, all outlive every stream.
struct StreamDeps {
  RunManager* runs;
  ModelRegistry* models;
  const Authorizer* authorizer;
  PeerChannels* peers;  // null: no cluster
  const std::atomic<bool>* stopping;
  StreamPump* pump;
  LiveStreams* live;
};

class SubscribeCall;

// What one kind of Subscribe stream sends.
class SubscribeSender {
 public:
  virtual ~SubscribeSender() = default;
  // Queues what is due now (SubscribeCall::Enqueue), ends the stream (Conclude), or waits
  // for a poke (WakeAt, or the subscription's listener). Called with the call's lock held
  // and no write pending.
  virtual void Step(SubscribeCall& call) = 0;
  // Without the call's lock, once, before the call finishes: stops the sender's helpers.
  virtual void Stop() {}
};

// Messages of the viewer that go to another replica instead (peer_proxy.h, follow_relays.h):
// `take` returns true for a message it sent on; `done` when the viewer half-closed.
struct Divert {
  std::function<bool(const v1::SubscribeRequest&)> take;
  std::function<void()> done;
};

class SubscribeCall final
    : public grpc::ServerBidiReactor<v1::SubscribeRequest, v1::SubscribeEvent>,
      public Pokeable,
      public std::enable_shared_from_this<SubscribeCall> {
 public:
  using Clock = std::chrono::steady_clock;

  // The reactor of a new call (gRPC holds it until OnDone).
  static grpc::ServerBidiReactor<v1::SubscribeRequest, v1::SubscribeEvent>* Open(
      grpc::CallbackServerContext* context, const StreamDeps& deps);
  SubscribeCall(grpc::CallbackServerContext* context, const StreamDeps& deps);

  // For senders, with the call's lock held (in Step).
  void Enqueue(v1::SubscribeEvent event);
  void Conclude(const grpc::Status& status);  // the first status given stays
  void WakeAt(Clock::time_point due);         // Step again then (the latest request only)
  bool stopping() const { return *deps_.stopping; }
  bool reader_done() const { return read_done_; }
  Subscription& subscription() { return *subscription_; }
  SentFrames& sent() { return sent_; }
  ReplayInbox* inbox() { return inbox_ ? &*inbox_ : nullptr; }
  const StreamDeps& deps() const { return deps_; }
  grpc::CallbackServerContext& context() { return *context_; }

  // For a sender's own threads (relays), without the call's lock.
  // Writes `event` after those queued; false when it could not (the call ends).
  bool WriteAndWait(const v1::SubscribeEvent& event);
  // The start is accepted (a relay connected): probe reports are read from now on.
  void StartReading(Divert divert);
  // Ends the stream with `status` (in a turn on the pump: never on the calling thread).
  void ConcludeLater(const grpc::Status& status);

  // Any thread: step the sender soon (on the pump).
  void Poke() override;

  // gRPC's reactions.
  void OnReadDone(bool ok) override;
  void OnWriteDone(bool ok) override;
  void OnCancel() override;
  void OnDone() override;

 private:
  enum class Phase { kAwaitStart, kStarting, kStreaming, kFinished };
  void Begin();
  void StartDeadline();
  void Start();                                         // subscribe_start.cc
  grpc::Status Accept();                                // subscribe_start.cc
  grpc::Status AttachHere(bool follow, int max_batch);  // subscribe_start.cc
  void Go(std::unique_ptr<SubscribeSender> sender, const std::string& subscribed);
  void HandleMessage();  // a read message (lock held)
  friend class PumpSteps;
  void RunStep();  // a step and a turn (pump_steps.h)
  // With the lock held: runs Pass in this call's turn (pump_steps.h).
  void Turn(std::unique_lock<std::mutex>& lock);
  void Pass(std::unique_lock<std::mutex>& lock);  // the sender's step if asked for, then Drive
  // In a turn: starts the next write, a read that is due, or finishes the call (lock held;
  // released and taken again around gRPC's calls).
  void Drive(std::unique_lock<std::mutex>& lock);
  void FinishNow(std::unique_lock<std::mutex>& lock);
  void Teardown();

  grpc::CallbackServerContext* const context_;
  const StreamDeps deps_;
  std::shared_ptr<SubscribeCall> self_;  // the reactor's own hold, until OnDone
  std::shared_ptr<Subscription> subscription_;
  LiveStreams::Id live_id_ = 0;
  SentFrames sent_;

  std::mutex mutex_;
  std::condition_variable written_;  // WriteAndWait's writes completed
  Phase phase_ = Phase::kAwaitStart;
  v1::SubscribeRequest request_;  // the read in flight
  v1::SubscribeRequest first_;    // the start
  std::optional<ReplayInbox> inbox_;
  std::unique_ptr<SubscribeSender> sender_;
  Divert divert_;
  bool read_wanted_ = false;  // a read is to be started (Drive)
  bool reading_ = false;      // probe reports are read (the start was accepted)
  bool read_done_ = false;    // the viewer half-closed (or the read failed)
  StreamWrites<v1::SubscribeEvent> writes_;
  bool goodbye_timer_ = false;
  bool goodbye_late_ = false;
  PumpSteps steps_;  // steps and turns
  int64_t accepted_ = 0;
  int64_t refused_ = 0;
};

}  // namespace mbstream
