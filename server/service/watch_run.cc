// SimulationService::WatchRun: progress (and optionally frames) of one run until it ends.
#include <chrono>
#include <thread>

#include "server/service/frame_batch.h"
#include "server/service/simulation_service.h"
#include "server/service/status_from_exception.h"
#include "server/wire/stats_conversion.h"

namespace mbstream {

grpc::Status SimulationService::WatchRun(grpc::ServerContext* context,
                                         const v1::WatchRunRequest* request,
                                         grpc::ServerWriter<v1::WatchEvent>* writer) {
  return Serve([&] {
    if (grpc::Status denied = authorizer_->Check(*context, Role::kView); !denied.ok()) {
      return denied;
    }
    using Clock = std::chrono::steady_clock;
    const std::string& run_id = request->run_id();
    v1::RunInfo info = runs_->Get(run_id);  // NOT_FOUND first
    const auto interval = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
        request->progress_interval_s() > 0 ? request->progress_interval_s() : 0.2));
    std::shared_ptr<Subscription> frames;
    if (request->frames()) frames = runs_->SubscribeRun(run_id, false);
    struct Unsubscribe {
      RunManager* runs;
      std::shared_ptr<Subscription> s;
      ~Unsubscribe() {
        if (s) runs->Unsubscribe(s);
      }
    } unsubscribe{runs_, frames};

    v1::WatchEvent event;
    Clock::time_point next_progress = Clock::now();
    std::deque<StreamEvent> events;
    for (;;) {
      if (context->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "client gone");
      if (stopping_) {
        return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                            "the server is shutting down; the run is INTERRUPTED");
      }
      if (Clock::now() >= next_progress) {
        info = runs_->Get(run_id);
        *event.mutable_progress() = info;
        if (!writer->Write(event)) return grpc::Status(grpc::StatusCode::CANCELLED, "client gone");
        if (IsFinalState(info.state())) return grpc::Status::OK;
        next_progress += interval;
      }
      const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(
          std::max(next_progress - Clock::now(), Clock::duration::zero()));
      if (!frames) {
        std::this_thread::sleep_for(std::min(wait, std::chrono::milliseconds(20)));
        if (runs_->Get(run_id).state() != info.state()) next_progress = Clock::now();
        continue;
      }
      events.clear();
      int64_t missed = 0;
      frames->Pop(std::min(wait, std::chrono::milliseconds(50)), 1024, &events, &missed);
      if (events.empty()) continue;
      if (events.front().kind == StreamEvent::Kind::kRunEnded) {
        next_progress = Clock::now();  // the final progress event right away
        continue;
      }
      if (events.front().kind != StreamEvent::Kind::kFrame) continue;
      FillFrameBatch(events, missed, event.mutable_frames());
      if (!writer->Write(event)) return grpc::Status(grpc::StatusCode::CANCELLED, "client gone");
    }
  });
}

}  // namespace mbstream
