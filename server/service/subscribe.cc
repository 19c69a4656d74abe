// SimulationService::Subscribe: the viewers' stream. Frames go out on this handler's thread;
// probe reports come in on a reader thread, get their round-trip latency and go to the run.
#include <spdlog/spdlog.h>

#include <condition_variable>
#include <mutex>
#include <thread>

#include "server/service/frame_batch.h"
#include "server/service/simulation_service.h"
#include "server/service/status_from_exception.h"

namespace mbstream {

namespace {

constexpr int kDefaultBatch = 256;

// Reads probe reports until the client half-closes or the call ends.
class ProbeReader {
 public:
  ProbeReader(grpc::ServerReaderWriter<v1::SubscribeEvent, v1::SubscribeRequest>* stream,
              RunManager* runs, const SentTimes* sent)
      : thread_([this, stream, runs, sent] { Read(stream, runs, sent); }) {}
  ~ProbeReader() { thread_.join(); }

  // Whether the client has half-closed (sent its last probe report).
  bool done() {
    std::lock_guard<std::mutex> lock(mutex_);
    return done_;
  }
  // Waits up to `timeout` for the client to half-close; returns whether it did.
  bool WaitDone(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return done_changed_.wait_for(lock, timeout, [&] { return done_; });
  }

 private:
  void Read(grpc::ServerReaderWriter<v1::SubscribeEvent, v1::SubscribeRequest>* stream,
            RunManager* runs, const SentTimes* sent) {
    v1::SubscribeRequest request;
    std::vector<v1::ProbeReport> one(1);
    while (stream->Read(&request)) {
      if (!request.has_probe()) continue;
      v1::ProbeReport& report = one[0];
      report = std::move(*request.mutable_probe());
      report.set_latency_us(
          sent->LatencyUs(report.run_id(), report.seq(), SentTimes::Clock::now()));
      try {
        runs->AddProbes(report.run_id(), one);
      } catch (const std::exception& error) {
        spdlog::warn("probe report for run {} dropped: {}", report.run_id(), error.what());
      }
    }
    std::lock_guard<std::mutex> lock(mutex_);
    done_ = true;
    done_changed_.notify_all();
  }

  std::mutex mutex_;
  std::condition_variable done_changed_;
  bool done_ = false;
  std::thread thread_;
};

}  // namespace

grpc::Status SimulationService::Subscribe(
    grpc::ServerContext* context,
    grpc::ServerReaderWriter<v1::SubscribeEvent, v1::SubscribeRequest>* stream) {
  return Serve([&]() -> grpc::Status {
    if (grpc::Status denied = authorizer_->Check(*context, Role::kView); !denied.ok()) {
      return denied;
    }
    v1::SubscribeRequest first;
    if (!stream->Read(&first) || !first.has_start()) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          "Subscribe: the first message must be `start` with a run_id or "
                          "follow = true");
    }
    const v1::SubscribeRequest::Start& start = first.start();
    const bool follow = start.target_case() == v1::SubscribeRequest::Start::kFollow;
    if (!follow && start.run_id().empty()) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          "Subscribe: start.run_id is empty; give a run id or follow = true");
    }
    const int max_batch = start.max_batch() > 0 ? start.max_batch() : kDefaultBatch;
    std::shared_ptr<Subscription> subscription =
        follow ? runs_->SubscribeFollow() : runs_->SubscribeRun(start.run_id(), true);
    struct Unsubscribe {
      RunManager* runs;
      std::shared_ptr<Subscription> s;
      ~Unsubscribe() { runs->Unsubscribe(s); }
    } unsubscribe{runs_, subscription};

    v1::SubscribeEvent event;
    event.set_subscribed(follow ? "follow" : start.run_id());
    if (!stream->Write(event)) {
      return grpc::Status(grpc::StatusCode::CANCELLED, "the subscriber went away");
    }
    SentTimes sent;
    ProbeReader reader(stream, runs_, &sent);
    std::deque<StreamEvent> events;
    grpc::Status status = grpc::Status::OK;
    bool one_run_ended = false;
    while (!one_run_ended) {
      if (context->IsCancelled()) {
        status = grpc::Status(grpc::StatusCode::CANCELLED, "the subscriber went away");
        break;
      }
      events.clear();
      int64_t missed = 0;
      const bool open =
          subscription->Pop(std::chrono::milliseconds(100), max_batch, &events, &missed);
      if (!open || stopping_) {
        status = grpc::Status(grpc::StatusCode::UNAVAILABLE, "the server is shutting down");
        break;
      }
      if (reader.done()) break;  // the viewer said goodbye: end the stream with OK
      if (events.empty()) continue;
      const StreamEvent& head = events.front();
      if (head.kind == StreamEvent::Kind::kFrame) {
        FillFrameBatch(events, missed, event.mutable_frames(), &sent);
      } else if (head.kind == StreamEvent::Kind::kRunStarted) {
        v1::SubscribeEvent::RunStarted* started = event.mutable_run_started();
        *started->mutable_run() = runs_->Get(head.run_id);
        std::shared_ptr<const CompiledModel> model = models_->Find(started->run().model_id());
        *started->mutable_model() = model->info;
        *started->mutable_bundle() = model->bundle;
      } else {
        *event.mutable_run_ended() = runs_->Get(head.run_id);
        one_run_ended = !follow;
      }
      if (!stream->Write(event)) {
        status = grpc::Status(grpc::StatusCode::CANCELLED, "the subscriber went away");
        break;
      }
    }
    // A one-run subscriber half-closes after run_ended (its last probes arrive before);
    // otherwise, or if it does not, end the call so the reader returns.
    if (!status.ok() || !reader.WaitDone(std::chrono::seconds(10))) context->TryCancel();
    return status;
  });
}

}  // namespace mbstream
