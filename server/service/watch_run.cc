// SimulationService::WatchRun: a WatchCall (watch_call.h) per stream.
#include <chrono>

#include "server/service/frame_batch.h"
#include "server/service/peer_proxy.h"
#include "server/service/rpc_roles.h"
#include "server/service/simulation_service.h"
#include "server/service/status_from_exception.h"
#include "server/service/watch_call.h"
#include "server/wire/stats_conversion.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kQueuedPoll = std::chrono::milliseconds(50);  // a queued run's claim
constexpr auto kStatePoll = std::chrono::milliseconds(20);   // a change of state, without frames
constexpr int kMaxBatch = 1024;

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

const grpc::Status& Gone() {
  static const grpc::Status gone(grpc::StatusCode::CANCELLED, "client gone");
  return gone;
}

}  // namespace

grpc::ServerWriteReactor<v1::WatchEvent>* SimulationService::WatchRun(
    grpc::CallbackServerContext* context, const v1::WatchRunRequest* request) {
  return WatchCall::Open(
      context, *request,
      StreamDeps{runs_, models_, authorizer_, peers_, &stopping_, &pump_, &live_});
}

grpc::ServerWriteReactor<v1::WatchEvent>* WatchCall::Open(grpc::CallbackServerContext* context,
                                                          const v1::WatchRunRequest& request,
                                                          const StreamDeps& deps) {
  auto call = std::make_shared<WatchCall>(context, request, deps);
  call->self_ = call;
  std::unique_lock<std::mutex> lock(call->mutex_);
  const grpc::Status begun = Serve([&] { return call->Begin(); });
  if (!begun.ok()) call->writes_.Conclude(begun);
  call->Turn(lock);
  return call.get();
}

WatchCall::WatchCall(grpc::CallbackServerContext* context, const v1::WatchRunRequest& request,
                     const StreamDeps& deps)
    : context_(context), request_(request), deps_(deps) {}

grpc::Status WatchCall::Begin() {
  if (grpc::Status denied = deps_.authorizer->Check(*context_, RoleOf("WatchRun")); !denied.ok()) {
    return denied;
  }
  interval_ = ProgressInterval(request_.progress_interval_s());
  info_ = deps_.runs->Get(request_.run_id());  // NOT_FOUND first
  next_progress_ = Clock::now();
  live_id_ = deps_.live->Add(weak_from_this());
  // A shared store: progress while the run is queued; once a replica claims it, watched
  // there (relayed) or here.
  if (deps_.runs->replica().shared_store() && deps_.peers != nullptr &&
      !PeerChannels::IsProxied(*context_)) {
    phase_ = Phase::kQueued;
  } else {
    Watch();
  }
  Step();
  return grpc::Status::OK;
}

void WatchCall::Watch() {
  phase_ = Phase::kWatching;
  // Every watch counts against the subscriber limit; only a watch with frames is attached
  // to the run.
  const std::string& run_id = request_.run_id();
  slot_ = request_.frames() ? deps_.runs->subscriptions().SubscribeRun(run_id, false)
                            : deps_.runs->subscriptions().New();
  if (request_.frames()) {
    slot_->SetListener([weak = weak_from_this()] {
      if (std::shared_ptr<WatchCall> call = weak.lock()) call->Poke();
    });
  }
}

void WatchCall::Poke() { steps_.Poke(*deps_.pump, shared_from_this()); }

void WatchCall::WakeAt(Clock::time_point due) {
  steps_.WakeAt(*deps_.pump, due, shared_from_this(), mutex_);
}

void WatchCall::RunStep() {
  std::unique_lock<std::mutex> lock(mutex_);
  steps_.Want();
  Turn(lock);
}

void WatchCall::Turn(std::unique_lock<std::mutex>& lock) {
  steps_.Turn([&] { Pass(lock); });
}

void WatchCall::Pass(std::unique_lock<std::mutex>& lock) {
  if (steps_.TakeWanted() && phase_ != Phase::kFinished && phase_ != Phase::kRelayed &&
      !writes_.conclusion() && writes_.idle()) {
    const grpc::Status failed = Serve([&] {
      Step();
      return grpc::Status::OK;
    });
    if (!failed.ok()) writes_.Conclude(failed);
  }
  Drive(lock);
}

void WatchCall::Step() {
  if (phase_ == Phase::kQueued) StepQueued();
  if (phase_ == Phase::kWatching) StepWatching();
}

void WatchCall::Progress(const v1::RunInfo& info) {
  v1::WatchEvent event;
  *event.mutable_progress() = info;
  writes_.Enqueue(std::move(event));
}

void WatchCall::StepQueued() {
  ReplicaControl::RunPlace place = deps_.runs->replica().Locate(request_.run_id());
  using Where = ReplicaControl::RunPlace::Where;
  if (place.where == Where::kElsewhere) {
    phase_ = Phase::kRelayed;
    relay_ = std::thread([self = shared_from_this(), owner = std::move(place.info)] {
      const grpc::Status status = Serve([&] {
        return ProxyWatchRun(
            *self->deps_.peers, *self->context_, self->request_,
            [&](const v1::WatchEvent& event) { return self->WriteAndWait(event); }, owner);
      });
      {
        std::lock_guard<std::mutex> lock(self->mutex_);
        self->writes_.Conclude(status);
      }
      self->Poke();  // finished in a turn on the pump, never here (Teardown joins this thread)
    });
    return;
  }
  if (place.where != Where::kQueued) {
    Watch();
    return;
  }
  if (deps_.stopping->load()) {
    writes_.Conclude(grpc::Status(grpc::StatusCode::UNAVAILABLE,
                                  "the server is shutting down; watch the run on another replica"));
    return;
  }
  if (Clock::now() >= next_progress_) {
    Progress(place.info);
    next_progress_ = Clock::now() + interval_;
  }
  WakeAt(Clock::now() + kQueuedPoll);
}

void WatchCall::StepWatching() {
  const bool frames = request_.frames();
  for (;;) {
    if (deps_.stopping->load()) {
      writes_.Conclude(grpc::Status(grpc::StatusCode::UNAVAILABLE,
                                    "the server is shutting down; the run is INTERRUPTED"));
      return;
    }
    if (Clock::now() >= next_progress_) {
      info_ = deps_.runs->Get(request_.run_id());
      next_progress_ = Clock::now() + interval_;
      // With frames, the final state goes out after the run-ended event (below).
      if (!frames || !IsFinalState(info_.state())) {
        Progress(info_);
        if (IsFinalState(info_.state())) {
          writes_.Conclude(grpc::Status::OK);
          return;
        }
      }
    }
    if (!frames) {  // a change of state is sent at once, the counters every interval
      if (deps_.runs->Get(request_.run_id()).state() != info_.state()) {
        next_progress_ = Clock::now();
        continue;
      }
      WakeAt(std::min(next_progress_, Clock::now() + kStatePoll));
      return;
    }
    events_.clear();
    int64_t missed = 0;
    slot_->Pop(std::chrono::milliseconds(0), kMaxBatch, &events_, &missed);
    if (events_.empty()) {
      WakeAt(next_progress_);  // or the subscription's listener, sooner
      return;
    }
    const StreamEvent::Kind kind = events_.front().kind;
    if (kind == StreamEvent::Kind::kFrame || missed > 0) {
      v1::WatchEvent event;
      FillFrameBatch(events_, missed, event.mutable_frames());
      writes_.Enqueue(std::move(event));
    }
    if (kind == StreamEvent::Kind::kRunEnded) {
      Progress(deps_.runs->Get(request_.run_id()));
      writes_.Conclude(grpc::Status::OK);
    }
    return;  // more after the write
  }
}

bool WatchCall::WriteAndWait(const v1::WatchEvent& event) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (writes_.conclusion() || phase_ == Phase::kFinished) return false;
  bool written = false, done = false;
  writes_.Enqueue(event, &written, &done);
  Poke();  // written in a turn on the pump, as Subscribe's
  written_.wait(lock, [&] { return done; });
  return written;
}

void WatchCall::OnWriteDone(bool ok) {
  std::unique_lock<std::mutex> lock(mutex_);
  writes_.Written(ok, Gone(), written_);
  if (!writes_.conclusion() && writes_.idle() && phase_ != Phase::kRelayed) Poke();
  Turn(lock);
}

void WatchCall::OnCancel() {
  std::unique_lock<std::mutex> lock(mutex_);
  writes_.Conclude(Gone());
  Turn(lock);
}

void WatchCall::Drive(std::unique_lock<std::mutex>& lock) {
  for (;;) {
    if (phase_ == Phase::kFinished) return;
    if (const v1::WatchEvent* event = writes_.Next()) {
      writes_.OutsideLock(lock, [&] { StartWrite(event); });
      continue;
    }
    if (!writes_.may_finish()) return;
    const grpc::Status status = *writes_.conclusion();
    phase_ = Phase::kFinished;
    lock.unlock();
    Teardown();
    Finish(status);
    lock.lock();
    return;
  }
}

void WatchCall::Teardown() {
  if (relay_.joinable()) relay_.join();
  if (slot_) {
    slot_->SetListener(nullptr);
    deps_.runs->subscriptions().Unsubscribe(slot_);
  }
  if (live_id_ != 0) deps_.live->Remove(live_id_);
}

void WatchCall::OnDone() {
  std::shared_ptr<WatchCall> self;  // freed here or by a pending task (or turn)
  std::lock_guard<std::mutex> lock(mutex_);
  self = std::move(self_);
}

}  // namespace mbstream
