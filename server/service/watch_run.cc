// SimulationService::WatchRun: progress (and optionally frames) of one run until it ends.
//
// A run integrating on another replica (shared store) is watched there: the owner's events are
// relayed unchanged (peer_proxy.h).
//
// With frames, the stream ends only after the subscription's run-ended event, which comes
// after the run's last frame: every frame is delivered or counted in a batch's `missed`
// before the final progress event.
#include <chrono>
#include <cmath>
#include <thread>

#include "common/check.h"
#include "server/service/frame_batch.h"
#include "server/service/peer_proxy.h"
#include "server/service/simulation_service.h"
#include "server/service/status_from_exception.h"
#include "server/wire/stats_conversion.h"

namespace mbstream {

namespace {

using Clock = std::chrono::steady_clock;
// The longest wait between looks at the client (gone?) and the server (stopping?).
constexpr auto kLook = std::chrono::milliseconds(250);

// s of wall time between progress events: 0 = the default; otherwise within the bounds.
Clock::duration ProgressInterval(double interval_s) {
  constexpr double kDefault = 0.2, kMin = 0.01, kMax = 60.0;
  if (interval_s == 0.0) interval_s = kDefault;
  if (!(interval_s >= kMin && interval_s <= kMax)) {
    throw InputError("WatchRun progress_interval_s is " + std::to_string(interval_s) +
                     "; give 0 (the default, 0.2 s) or a value from 0.01 to 60 s");
  }
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(interval_s));
}

}  // namespace

grpc::Status SimulationService::WatchRun(grpc::ServerContext* context,
                                         const v1::WatchRunRequest* request,
                                         grpc::ServerWriter<v1::WatchEvent>* writer) {
  return Admit(*context, "WatchRun", [&]() -> grpc::Status {
    const Clock::duration interval = ProgressInterval(request->progress_interval_s());
    const std::string& run_id = request->run_id();
    v1::RunInfo info = runs_->Get(run_id);  // NOT_FOUND first
    Clock::time_point next_progress = Clock::now();
    // A shared store: progress while the run is queued; once a replica claims it, watched
    // there (proxied) or here.
    const grpc::Status gone(grpc::StatusCode::CANCELLED, "client gone");
    v1::WatchEvent event;
    if (runs_->shared_store() && peers_ != nullptr && !PeerChannels::IsProxied(*context)) {
      for (RunManager::RunPlace place = runs_->Locate(run_id);; place = runs_->Locate(run_id)) {
        if (place.where == RunManager::RunPlace::Where::kElsewhere) {
          return ProxyWatchRun(*peers_, context, *request, writer, place.info);
        }
        if (place.where != RunManager::RunPlace::Where::kQueued) break;
        if (context->IsCancelled()) return gone;
        if (stopping_) {
          return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                              "the server is shutting down; watch the run on another replica");
        }
        if (Clock::now() >= next_progress) {
          *event.mutable_progress() = place.info;
          if (!writer->Write(event)) return gone;
          next_progress = Clock::now() + interval;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    }
    // Every watch counts against the subscriber limit (it holds a thread); only a watch
    // with frames is attached to the run.
    std::shared_ptr<Subscription> slot =
        request->frames() ? runs_->SubscribeRun(run_id, false) : runs_->NewSubscription();
    struct Unsubscribe {
      RunManager* runs;
      std::shared_ptr<Subscription> s;
      ~Unsubscribe() { runs->Unsubscribe(s); }
    } unsubscribe{runs_, slot};
    Subscription* frames = request->frames() ? slot.get() : nullptr;

    std::deque<StreamEvent> events;
    for (;;) {
      if (context->IsCancelled()) return gone;
      if (stopping_) {
        return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                            "the server is shutting down; the run is INTERRUPTED");
      }
      if (Clock::now() >= next_progress) {
        info = runs_->Get(run_id);
        next_progress = Clock::now() + interval;
        // With frames, the final state goes out after the run-ended event (below).
        if (!frames || !IsFinalState(info.state())) {
          *event.mutable_progress() = info;
          if (!writer->Write(event)) return gone;
          if (IsFinalState(info.state())) return grpc::Status::OK;
        }
      }
      const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(
          std::max(next_progress - Clock::now(), Clock::duration::zero()));
      if (!frames) {  // a change of state is sent at once, the counters every interval
        const Clock::time_point look = Clock::now() + std::min(wait, kLook);
        if (runs_->AwaitChange(run_id, info.state(), look).state() != info.state()) {
          next_progress = Clock::now();
        }
        continue;
      }
      events.clear();
      int64_t missed = 0;
      frames->Pop(std::min(wait, std::chrono::milliseconds(50)), 1024, &events, &missed);
      if (events.empty()) continue;
      const StreamEvent::Kind kind = events.front().kind;
      if (kind == StreamEvent::Kind::kFrame || missed > 0) {
        FillFrameBatch(events, missed, event.mutable_frames());
        if (!writer->Write(event)) return gone;
      }
      if (kind == StreamEvent::Kind::kRunEnded) {
        *event.mutable_progress() = runs_->Get(run_id);
        return writer->Write(event) ? grpc::Status::OK : gone;
      }
    }
  });
}

}  // namespace mbstream
