// SimulationService::Subscribe: the viewers' stream. Frames go out on this handler's thread;
// the `start` message and then probe reports come in on a reader thread (so a stream costs
// two threads: gRPC's handler thread and the reader). A stream counts against the
// subscriber limit from its first moment, and one that sends no `start` within the limit's
// deadline is ended, so idle streams cannot pile up threads.
#include <spdlog/spdlog.h>

#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "server/service/follow_relays.h"
#include "server/service/frame_batch.h"
#include "server/service/peer_proxy.h"
#include "server/service/replay_stream.h"
#include "server/service/simulation_service.h"
#include "server/service/status_from_exception.h"

namespace mbstream {

namespace {

constexpr int kDefaultBatch = 256;
constexpr int kMaxBatch = 4096;

using Stream = grpc::ServerReaderWriter<v1::SubscribeEvent, v1::SubscribeRequest>;

// Messages of the viewer that go to another replica instead (peer_proxy.h, follow_relays.h):
// `take` returns true for a message it sent on; `done` when the viewer half-closed.
struct Divert {
  std::function<bool(const v1::SubscribeRequest&)> take;
  std::function<void()> done;
};

// The stream's writes: the handler's and, on a follow stream, its relays' (one at a time).
class LockedWriter {
 public:
  explicit LockedWriter(Stream* stream) : stream_(stream) {}
  bool Write(const v1::SubscribeEvent& event) {
    std::lock_guard<std::mutex> lock(mutex_);
    return stream_->Write(event);
  }

 private:
  Stream* const stream_;
  std::mutex mutex_;
};

// Reads the stream's `start` message; then, once the handler has accepted it (Go), probe
// reports until the client half-closes or the call ends. A report is checked against the
// frames this stream sent (SentFrames) and kept with its run; refused reports are counted,
// never stored. Until Go the reader is not reading, so the handler may refuse the start with
// its own status.
class SubscribeReader {
 public:
  SubscribeReader(grpc::ServerContext* context, Stream* stream, RunManager* runs, SentFrames* sent)
      : context_(context), thread_([this, stream, runs, sent] { Read(stream, runs, sent); }) {}
  // A reader blocked in Read (no first message yet, or reading probes) returns only when the
  // call ends: end it first (the client then sees CANCELLED).
  ~SubscribeReader() {
    bool blocked = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      blocked = !first_read_ || (go_ && !done_);
      stop_ = true;
    }
    changed_.notify_all();
    if (blocked) context_->TryCancel();
    thread_.join();
  }

  // Waits up to `timeout` for the first message; empty when it did not come (or the client
  // half-closed or sent something else first).
  std::optional<v1::SubscribeRequest> WaitStart(std::chrono::duration<double> timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait_for(lock, timeout, [&] { return first_read_; });
    return first_;
  }
  // The start was accepted: read probe reports from now on (and, for a replay, its time
  // controls; its probe reports then go to `inbox`, which must outlive the reader).
  void Go(ReplayInbox* inbox = nullptr, Divert divert = {}) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      go_ = true;
      inbox_ = inbox;
      divert_ = std::move(divert);
    }
    changed_.notify_all();
  }
  // Whether the reader reads probe reports still (Go, and the client has not half-closed).
  bool reading() {
    std::lock_guard<std::mutex> lock(mutex_);
    return go_ && !done_;
  }
  // Whether the client has half-closed (or sent no start).
  bool done() {
    std::lock_guard<std::mutex> lock(mutex_);
    return done_;
  }
  // Waits up to `timeout` for the client to half-close; returns whether it did.
  bool WaitDone(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, timeout, [&] { return done_; });
  }
  int64_t accepted() const { return accepted_; }
  int64_t refused() const { return refused_; }

 private:
  void Read(Stream* stream, RunManager* runs, SentFrames* sent) {
    v1::SubscribeRequest request;
    const bool started = stream->Read(&request) && request.has_start();
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (started) first_ = request;
      first_read_ = true;
      done_ = !started;
      changed_.notify_all();
      if (!started) return;
      changed_.wait(lock, [&] { return go_ || stop_; });
      if (!go_) return;
    }
    std::vector<v1::ProbeReport> one(1);
    while (stream->Read(&request)) {
      if (divert_.take && divert_.take(request)) continue;
      if (inbox_ && request.has_control()) inbox_->PushControl(request.control());
      if (!request.has_probe()) continue;
      v1::ProbeReport& report = one[0];
      report = std::move(*request.mutable_probe());
      const std::string refusal = sent->Accept(report, SentFrames::Clock::now());
      if (refusal.empty() &&
          (inbox_ ? inbox_->AddProbe(report) : runs->AddProbes(report.run_id(), one))) {
        ++accepted_;
      } else if (refused_++ == 0) {
        spdlog::warn("probe report for frame {} refused: {}", report.seq(),
                     refusal.empty() ? "its run has ended and been stored" : refusal);
      }
    }
    if (inbox_) inbox_->Wake();
    if (divert_.done) divert_.done();
    std::lock_guard<std::mutex> lock(mutex_);
    done_ = true;
    changed_.notify_all();
  }

  grpc::ServerContext* const context_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<v1::SubscribeRequest> first_;
  bool first_read_ = false;
  bool go_ = false;
  bool stop_ = false;
  bool done_ = false;
  ReplayInbox* inbox_ = nullptr;  // set by Go, before the reader reads past the start
  Divert divert_;                 // set by Go, as inbox_
  std::atomic<int64_t> accepted_{0};
  std::atomic<int64_t> refused_{0};
  std::thread thread_;
};

// What a Subscribe stream follows, and where it finds runs and models.
struct SubscribeTarget {
  RunManager* runs;
  ModelRegistry* models;
  const std::atomic<bool>* stopping_flag;
  bool follow = false;
  int max_batch = kDefaultBatch;
  FollowRelays* relays = nullptr;  // a follow stream's runs of other replicas (shared store)

  bool stopping() const { return *stopping_flag; }
  void FillRunStarted(const std::string& run_id, v1::SubscribeEvent::RunStarted* started) const {
    *started->mutable_run() = runs->Get(run_id);
    *started->mutable_model() = runs->ModelInfo(started->run().model_id());
    *started->mutable_bundle() = models->Bundle(started->model().id());
  }
};

// Sends the subscription's events until its one run ended, the client left or said goodbye,
// or the server stops.
grpc::Status SendEvents(grpc::ServerContext* context, LockedWriter* stream,
                        const SubscribeTarget& target, Subscription* subscription,
                        SubscribeReader* reader, SentFrames* sent) {
  const grpc::Status gone(grpc::StatusCode::CANCELLED, "the subscriber went away");
  v1::SubscribeEvent event;
  std::deque<StreamEvent> events;
  for (;;) {
    if (context->IsCancelled()) return gone;
    events.clear();
    int64_t missed = 0;
    const bool open =
        subscription->Pop(std::chrono::milliseconds(100), target.max_batch, &events, &missed);
    if (!open || target.stopping()) {
      const std::string reason = "the server is shutting down; reconnect later";
      event.set_closing(reason);
      (void)stream->Write(event);  // the viewer half-closes; the call ends UNAVAILABLE
      return grpc::Status(grpc::StatusCode::UNAVAILABLE, reason);
    }
    if (reader->done()) return grpc::Status::OK;  // the viewer said goodbye
    if (events.empty()) continue;
    const StreamEvent& head = events.front();
    if (head.kind == StreamEvent::Kind::kRemoteRun) {
      if (target.relays != nullptr) target.relays->Open(head.run_id);
      continue;
    }
    if (head.kind == StreamEvent::Kind::kFrame || missed > 0) {
      FillFrameBatch(events, missed, event.mutable_frames(), sent);
      if (!stream->Write(event)) return gone;
    }
    if (head.kind == StreamEvent::Kind::kFrame) continue;
    if (head.kind == StreamEvent::Kind::kRunStarted) {
      target.FillRunStarted(head.run_id, event.mutable_run_started());
    } else {
      *event.mutable_run_ended() = target.runs->Get(head.run_id);
    }
    if (!stream->Write(event)) return gone;
    if (head.kind == StreamEvent::Kind::kRunEnded && !target.follow) return grpc::Status::OK;
  }
}

// The events of the owner's stream, passed on unchanged until it ends; its end as this
// stream's. The owner gone: `closing` (the viewer half-closes and reconnects), UNAVAILABLE.
grpc::Status RelaySubscribe(Stream* stream, PeerSubscribe* upstream) {
  v1::SubscribeEvent event;
  while (upstream->Read(&event)) {
    if (!stream->Write(event)) {
      upstream->Cancel();
      (void)upstream->Finish();
      return grpc::Status(grpc::StatusCode::CANCELLED, "the subscriber went away");
    }
  }
  const grpc::Status status = upstream->Finish();
  if (status.error_code() == grpc::StatusCode::UNAVAILABLE) {
    event.set_closing(status.error_message());
    (void)stream->Write(event);
  }
  return status;
}

}  // namespace

grpc::Status SimulationService::Subscribe(grpc::ServerContext* context, Stream* stream) {
  return Admit(*context, "Subscribe", [&]() -> grpc::Status {
    // Counted before anything is read: idle streams count against the subscriber limit.
    std::shared_ptr<Subscription> subscription = runs_->NewSubscription();
    struct Unsubscribe {
      RunManager* runs;
      std::shared_ptr<Subscription> s;
      ~Unsubscribe() { runs->Unsubscribe(s); }
    } unsubscribe{runs_, subscription};

    SentFrames sent;
    std::optional<ReplayInbox> inbox;  // a replay's; outlives the reader, which feeds it
    // A run of another replica (its owner's stream), or a follow stream's relays of such
    // runs: both outlive the reader, which sends them the viewer's messages.
    std::optional<PeerSubscribe> upstream;
    LockedWriter writer(stream);
    std::optional<FollowRelays> relays;
    SubscribeReader reader(context, stream, runs_, &sent);
    const grpc::Status status = Serve([&]() -> grpc::Status {
      const std::optional<v1::SubscribeRequest> first =
          reader.WaitStart(std::chrono::duration<double>(runs_->limits().subscribe_start_s));
      if (!first) {
        return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            "Subscribe: the first message must be `start` with a run_id or "
                            "follow = true, sent within " +
                                std::to_string(runs_->limits().subscribe_start_s) + " s");
      }
      const v1::SubscribeRequest::Start& start = first->start();
      SubscribeTarget target{runs_, models_, &stopping_};
      target.follow = start.target_case() == v1::SubscribeRequest::Start::kFollow;
      if (!target.follow && start.run_id().empty()) {
        return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            "Subscribe: start.run_id is empty; give a run id or follow = true");
      }
      if (start.max_batch() < 0 || start.max_batch() > kMaxBatch) {
        return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            "Subscribe: start.max_batch is " + std::to_string(start.max_batch()) +
                                "; give 0 (the server's choice) up to " +
                                std::to_string(kMaxBatch));
      }
      target.max_batch = start.max_batch() > 0 ? start.max_batch() : kDefaultBatch;
      if (start.has_replay() && target.follow) {
        return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            "Subscribe: start.replay needs a run_id, not follow");
      }
      if (std::optional<ReplayPlan> plan =
              start.has_replay() ? PlanReplay(*runs_, start) : std::nullopt) {
        v1::ProbeSet set;
        set.set_id(runs_->NewProbeSetId());
        set.set_run_id(plan->run.id());
        set.set_viewer(start.replay().viewer());
        set.set_scene(start.replay().scene());
        inbox.emplace(runs_, set);
        reader.Go(&*inbox);
        v1::SubscribeEvent event;
        event.set_subscribed("replay " + plan->run.id());
        if (!stream->Write(event)) {
          return grpc::Status(grpc::StatusCode::CANCELLED, "the subscriber went away");
        }
        const ReplayStreamContext io{context,         stream,  runs_, models_,
                                     &stopping_,      &*inbox, &sent, [&] { return reader.done(); },
                                     target.max_batch};
        return SendReplay(io, *plan);
      }
      if (!target.follow) {
        if (std::optional<v1::RunInfo> owner =
                RemoteOwner(peers_, *runs_, start.run_id(), *context, stopping_, true)) {
          upstream.emplace(*peers_, *context, *owner, *first);  // throws UNAVAILABLE
          reader.Go(nullptr,
                    {[&](const v1::SubscribeRequest& r) { return upstream->Write(r), true; },
                     [&] { upstream->WritesDone(); }});
          return RelaySubscribe(stream, &*upstream);
        }
      }
      if (target.follow) {
        runs_->AttachFollow(subscription);
        if (peers_ != nullptr && runs_->shared_store()) {
          relays.emplace(
              peers_, runs_, context,
              [&writer](const v1::SubscribeEvent& e) { return writer.Write(e); }, target.max_batch);
          target.relays = &*relays;
        }
      } else {
        runs_->AttachRun(subscription, start.run_id(), true);
      }
      if (relays) {
        reader.Go(nullptr, {[&](const v1::SubscribeRequest& r) { return relays->Divert(r); }, {}});
      } else {
        reader.Go();
      }
      v1::SubscribeEvent event;
      event.set_subscribed(target.follow ? "follow" : start.run_id());
      if (!writer.Write(event)) {
        return grpc::Status(grpc::StatusCode::CANCELLED, "the subscriber went away");
      }
      const grpc::Status sent_all =
          SendEvents(context, &writer, target, subscription.get(), &reader, &sent);
      if (relays) relays->Stop();
      return sent_all;
    });
    // A one-run subscriber half-closes after run_ended (its last probes arrive before), and
    // every viewer after `closing`; otherwise, or if it does not, end the call so that the
    // reader returns (the client then sees CANCELLED).
    const bool goodbye_expected =
        status.ok() || status.error_code() == grpc::StatusCode::UNAVAILABLE;
    if (reader.reading() &&
        (!goodbye_expected ||
         !reader.WaitDone(status.ok() ? std::chrono::seconds(10) : std::chrono::seconds(2)))) {
      context->TryCancel();
    }
    if (reader.refused() > 0) {
      spdlog::warn("Subscribe stream ended: {} probe reports stored, {} refused", reader.accepted(),
                   reader.refused());
    }
    return status;
  });
}

}  // namespace mbstream
