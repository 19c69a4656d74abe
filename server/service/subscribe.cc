// SubscribeCall's life (subscribe_call.h): reads, writes, deadlines and the end. The start
// message's handling is in subscribe_start.cc, the senders in subscribe_senders.cc and
// replay_stream.cc.
//
// Locking: one mutex per call guards its state; gRPC's Start* and Finish are called only in
// the call's turn (one thread at a time: pump_steps.h) and never with the mutex held (gRPC
// may run a reaction inline; StreamWrites::OutsideLock). Every entry (a reaction, a pump
// task) changes the state under the mutex, then asks for a turn.
#include <spdlog/spdlog.h>

#include "server/service/rpc_roles.h"
#include "server/service/simulation_service.h"
#include "server/service/status_from_exception.h"
#include "server/service/subscribe_call.h"

namespace mbstream {

namespace {

const grpc::Status& Gone() {
  static const grpc::Status gone(grpc::StatusCode::CANCELLED, "the subscriber went away");
  return gone;
}

}  // namespace

grpc::ServerBidiReactor<v1::SubscribeRequest, v1::SubscribeEvent>* SubscribeCall::Open(
    grpc::CallbackServerContext* context, const StreamDeps& deps) {
  auto call = std::make_shared<SubscribeCall>(context, deps);
  call->self_ = call;
  call->Begin();
  return call.get();
}

SubscribeCall::SubscribeCall(grpc::CallbackServerContext* context, const StreamDeps& deps)
    : context_(context), deps_(deps) {}

void SubscribeCall::Begin() {
  std::unique_lock<std::mutex> lock(mutex_);
  grpc::Status admitted = deps_.authorizer->Check(*context_, RoleOf("Subscribe"));
  if (admitted.ok()) {
    // Counted before anything is read: idle streams count against the subscriber limit.
    admitted = Serve([&] {
      subscription_ = deps_.runs->subscriptions().New();
      return grpc::Status::OK;
    });
  }
  if (!admitted.ok()) {
    Conclude(admitted);
    Turn(lock);
    return;
  }
  live_id_ = deps_.live->Add(weak_from_this());
  subscription_->SetListener([weak = weak_from_this()] {
    if (std::shared_ptr<SubscribeCall> call = weak.lock()) call->Poke();
  });
  const auto deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double>(deps_.runs->limits().subscribe_start_s));
  deps_.pump->PostAt(deadline, [weak = weak_from_this()] {  // an ended call is not kept
    if (std::shared_ptr<SubscribeCall> self = weak.lock()) self->StartDeadline();
  });
  read_wanted_ = true;
  Turn(lock);
}

void SubscribeCall::StartDeadline() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (phase_ != Phase::kAwaitStart) return;
  Conclude(grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        "Subscribe: the first message must be `start` with a run_id or "
                        "follow = true, sent within " +
                            std::to_string(deps_.runs->limits().subscribe_start_s) + " s"));
  Turn(lock);
}

void SubscribeCall::Enqueue(v1::SubscribeEvent event) { writes_.Enqueue(std::move(event)); }

void SubscribeCall::Conclude(const grpc::Status& status) { writes_.Conclude(status); }

void SubscribeCall::WakeAt(Clock::time_point due) {
  steps_.WakeAt(*deps_.pump, due, shared_from_this(), mutex_);
}

void SubscribeCall::Poke() { steps_.Poke(*deps_.pump, shared_from_this()); }

void SubscribeCall::RunStep() {
  std::unique_lock<std::mutex> lock(mutex_);
  steps_.Want();
  Turn(lock);
}

void SubscribeCall::Turn(std::unique_lock<std::mutex>& lock) {
  steps_.Turn([&] { Pass(lock); });
}

void SubscribeCall::Pass(std::unique_lock<std::mutex>& lock) {
  if (steps_.TakeWanted() && phase_ == Phase::kStreaming && sender_ && !writes_.conclusion() &&
      writes_.idle()) {
    const grpc::Status failed = Serve([&] {
      sender_->Step(*this);
      return grpc::Status::OK;
    });
    if (!failed.ok()) Conclude(failed);
  }
  Drive(lock);
}

bool SubscribeCall::WriteAndWait(const v1::SubscribeEvent& event) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (writes_.conclusion() || phase_ == Phase::kFinished) return false;
  bool written = false, done = false;
  writes_.Enqueue(event, &written, &done);
  // Written in a turn on the pump: this thread must never finish the call (Teardown joins it).
  Poke();
  written_.wait(lock, [&] { return done; });
  return written;
}

void SubscribeCall::StartReading(Divert divert) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (writes_.conclusion()) return;
  divert_ = std::move(divert);
  reading_ = true;
  read_wanted_ = true;
  Poke();  // a turn on the pump, as WriteAndWait's
}

void SubscribeCall::ConcludeLater(const grpc::Status& status) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    Conclude(status);
  }
  Poke();
}

void SubscribeCall::OnReadDone(bool ok) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (phase_ == Phase::kFinished) return;
  if (phase_ == Phase::kAwaitStart) {
    if (!ok || !request_.has_start()) {
      read_done_ = true;
      Conclude(grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            "Subscribe: the first message must be `start` with a run_id or "
                            "follow = true, sent within " +
                                std::to_string(deps_.runs->limits().subscribe_start_s) + " s"));
      Turn(lock);
      return;
    }
    phase_ = Phase::kStarting;
    first_ = std::move(request_);
    deps_.pump->Post([self = shared_from_this()] { self->Start(); });
    return;
  }
  if (!ok) {  // the viewer half-closed: its goodbye
    read_done_ = true;
    if (inbox_) inbox_->Wake();
    if (divert_.done) divert_.done();
    if (!writes_.conclusion()) Poke();  // the sender ends the stream
    Turn(lock);
    return;
  }
  HandleMessage();
  read_wanted_ = true;
  Turn(lock);
}

void SubscribeCall::HandleMessage() {
  v1::SubscribeRequest& request = request_;
  if (divert_.take && divert_.take(request)) return;
  if (inbox_ && request.has_control()) {
    inbox_->PushControl(request.control());
    Poke();
  }
  if (!request.has_probe()) return;
  v1::ProbeReport report = std::move(*request.mutable_probe());
  const std::string refusal = sent_.Accept(report, SentFrames::Clock::now());
  bool stored = false;
  if (refusal.empty()) {
    if (inbox_) {
      stored = inbox_->AddProbe(report);
    } else {
      std::vector<v1::ProbeReport> one(1, std::move(report));
      stored = deps_.runs->subscriptions().AddProbes(one[0].run_id(), one);
      report = std::move(one[0]);
    }
  }
  if (stored) {
    ++accepted_;
  } else if (refused_++ == 0) {
    spdlog::warn("probe report for frame {} refused: {}", report.seq(),
                 refusal.empty() ? "its run has ended and been stored" : refusal);
  }
}

void SubscribeCall::OnWriteDone(bool ok) {
  std::unique_lock<std::mutex> lock(mutex_);
  writes_.Written(ok, Gone(), written_);
  if (!writes_.conclusion() && writes_.idle()) Poke();
  Turn(lock);
}

void SubscribeCall::OnCancel() {
  std::unique_lock<std::mutex> lock(mutex_);
  Conclude(Gone());
  Turn(lock);
}

void SubscribeCall::Drive(std::unique_lock<std::mutex>& lock) {
  for (;;) {
    if (phase_ == Phase::kFinished) return;
    if (read_wanted_) {
      read_wanted_ = false;
      writes_.OutsideLock(lock, [&] { StartRead(&request_); });
      continue;
    }
    if (const v1::SubscribeEvent* event = writes_.Next()) {
      writes_.OutsideLock(lock, [&] { StartWrite(event); });
      continue;
    }
    if (!writes_.may_finish() || phase_ == Phase::kStarting) return;
    FinishNow(lock);
    return;
  }
}

void SubscribeCall::FinishNow(std::unique_lock<std::mutex>& lock) {
  const grpc::Status status = *writes_.conclusion();
  const bool reading = reading_ && !read_done_;
  // A one-run subscriber half-closes after run_ended (its last probes arrive before), and
  // every viewer after `closing`: wait for that goodbye a while.
  const bool goodbye_expected = status.ok() || status.error_code() == grpc::StatusCode::UNAVAILABLE;
  if (reading && goodbye_expected && !goodbye_late_) {
    if (!goodbye_timer_) {
      goodbye_timer_ = true;
      const auto wait = status.ok() ? std::chrono::seconds(10) : std::chrono::seconds(2);
      deps_.pump->PostAt(Clock::now() + wait, [weak = weak_from_this()] {
        std::shared_ptr<SubscribeCall> self = weak.lock();
        if (!self) return;
        std::unique_lock<std::mutex> lock(self->mutex_);
        self->goodbye_late_ = true;
        self->Turn(lock);
      });
    }
    return;
  }
  phase_ = Phase::kFinished;
  lock.unlock();
  Teardown();
  // Otherwise, or if it does not, end the call (the client then sees CANCELLED).
  if (reading) context_->TryCancel();
  Finish(status);
  lock.lock();
}

void SubscribeCall::Teardown() {
  if (subscription_) {
    subscription_->SetListener(nullptr);
    if (sender_) sender_->Stop();
    deps_.runs->subscriptions().Unsubscribe(subscription_);
    deps_.live->Remove(live_id_);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  inbox_.reset();   // stores the replay's last probe reports before the call ends
  sender_.reset();  // a replay's chunks: no read diverts from now on (phase_ kFinished)
  if (refused_ > 0) {
    spdlog::warn("Subscribe stream ended: {} probe reports stored, {} refused", accepted_,
                 refused_);
  }
}

void SubscribeCall::OnDone() {
  std::shared_ptr<SubscribeCall> self;  // freed here or by a pending task (or turn)
  std::lock_guard<std::mutex> lock(mutex_);
  self = std::move(self_);
}

grpc::ServerBidiReactor<v1::SubscribeRequest, v1::SubscribeEvent>* SimulationService::Subscribe(
    grpc::CallbackServerContext* context) {
  return SubscribeCall::Open(
      context, StreamDeps{runs_, models_, authorizer_, peers_, &stopping_, &pump_, &live_});
}

}  // namespace mbstream
