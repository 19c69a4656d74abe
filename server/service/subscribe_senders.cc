#include "server/service/subscribe_senders.h"

#include <deque>
#include <thread>

#include "server/service/frame_batch.h"
#include "server/service/peer_proxy.h"
#include "server/service/status_from_exception.h"

namespace mbstream {

namespace {

class LiveSender final : public SubscribeSender {
 public:
  LiveSender(bool follow, int max_batch, bool contacts, std::unique_ptr<FollowRelays> relays)
      : follow_(follow), max_batch_(max_batch), contacts_(contacts), relays_(std::move(relays)) {}

  void Step(SubscribeCall& call) override {
    for (;;) {
      events_.clear();
      int64_t missed = 0;
      const bool open =
          call.subscription().Pop(std::chrono::milliseconds(0), max_batch_, &events_, &missed);
      if (!open || call.stopping()) {
        const std::string reason = "the server is shutting down; reconnect later";
        v1::SubscribeEvent closing;
        closing.set_closing(reason);
        call.Enqueue(std::move(closing));  // the viewer half-closes; the call ends UNAVAILABLE
        call.Conclude(grpc::Status(grpc::StatusCode::UNAVAILABLE, reason));
        return;
      }
      if (call.reader_done()) {  // the viewer said goodbye
        call.Conclude(grpc::Status::OK);
        return;
      }
      if (events_.empty()) return;  // the subscription's listener pokes again
      const StreamEvent& head = events_.front();
      if (head.kind == StreamEvent::Kind::kRemoteRun) {
        if (relays_) relays_->Open(head.run_id);
        continue;
      }
      if (head.kind == StreamEvent::Kind::kFrame || missed > 0) {
        v1::SubscribeEvent frames;
        FillFrameBatch(events_, missed, frames.mutable_frames(), &call.sent(), contacts_);
        call.Enqueue(std::move(frames));
      }
      if (head.kind == StreamEvent::Kind::kFrame) return;  // more after the write
      v1::SubscribeEvent event;
      RunManager& runs = *call.deps().runs;
      if (head.kind == StreamEvent::Kind::kRunStarted) {
        v1::SubscribeEvent::RunStarted* started = event.mutable_run_started();
        *started->mutable_run() = runs.Get(head.run_id);
        *started->mutable_model() = runs.replica().ModelInfo(started->run().model_id());
        *started->mutable_bundle() = call.deps().models->Bundle(started->model().id());
      } else {
        *event.mutable_run_ended() = runs.Get(head.run_id);
      }
      call.Enqueue(std::move(event));
      if (head.kind == StreamEvent::Kind::kRunEnded && !follow_) call.Conclude(grpc::Status::OK);
      return;
    }
  }

  void Stop() override {
    if (relays_) relays_->Stop();
  }

 private:
  const bool follow_;
  const int max_batch_;
  const bool contacts_;
  const std::unique_ptr<FollowRelays> relays_;
  std::deque<StreamEvent> events_;
};

// The events of the owner's stream, passed on unchanged until it ends; its end as this
// stream's. The owner gone: `closing` (the viewer half-closes and reconnects), UNAVAILABLE.
grpc::Status Relay(SubscribeCall& call, PeerSubscribe& upstream) {
  v1::SubscribeEvent event;
  while (upstream.Read(&event)) {
    if (!call.WriteAndWait(event)) {
      upstream.Cancel();
      (void)upstream.Finish();
      return grpc::Status(grpc::StatusCode::CANCELLED, "the subscriber went away");
    }
  }
  const grpc::Status status = upstream.Finish();
  if (status.error_code() == grpc::StatusCode::UNAVAILABLE) {
    event.set_closing(status.error_message());
    (void)call.WriteAndWait(event);
  }
  return status;
}

class RelaySender final : public SubscribeSender {
 public:
  RelaySender(SubscribeCall& call, v1::RunInfo owner, const v1::SubscribeRequest& start)
      : thread_([this, &call, owner = std::move(owner), start] { Run(call, owner, start); }) {}
  ~RelaySender() override { Stop(); }

  void Step(SubscribeCall&) override {}  // the thread writes
  void Stop() override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopped_ = true;
      if (upstream_) upstream_->Cancel();
    }
    if (thread_.joinable()) thread_.join();
  }

 private:
  void Run(SubscribeCall& call, const v1::RunInfo& owner, const v1::SubscribeRequest& start) {
    std::unique_ptr<PeerSubscribe> connected;
    const grpc::Status status = Serve([&] {
      connected = std::make_unique<PeerSubscribe>(*call.deps().peers, call.context(), owner,
                                                  start);  // throws UNAVAILABLE
      return grpc::Status::OK;
    });
    if (!status.ok()) {
      call.ConcludeLater(status);
      return;
    }
    PeerSubscribe* upstream = connected.get();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      upstream_ = std::move(connected);
      if (stopped_) upstream->Cancel();
    }
    call.StartReading(
        {[upstream](const v1::SubscribeRequest& r) { return upstream->Write(r), true; },
         [upstream] { upstream->WritesDone(); }});
    call.ConcludeLater(Relay(call, *upstream));
  }

  std::mutex mutex_;
  bool stopped_ = false;
  std::unique_ptr<PeerSubscribe> upstream_;  // once connected
  std::thread thread_;
};

}  // namespace

std::unique_ptr<SubscribeSender> NewLiveSender(bool follow, int max_batch, bool contacts,
                                               std::unique_ptr<FollowRelays> relays) {
  return std::make_unique<LiveSender>(follow, max_batch, contacts, std::move(relays));
}

std::unique_ptr<SubscribeSender> NewRelaySender(SubscribeCall& call, v1::RunInfo owner,
                                                const v1::SubscribeRequest& start) {
  return std::make_unique<RelaySender>(call, std::move(owner), start);
}

}  // namespace mbstream
