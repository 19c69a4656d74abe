// SubscribeCall's start message (subscribe_call.h): checked, then the stream's sender chosen
// by what it asks for. Runs on the pump; a run queued in a shared store is looked at again
// every 50 ms until a replica claims it (then relayed from there, or served here).
#include "server/service/replay_stream.h"
#include "server/service/status_from_exception.h"
#include "server/service/subscribe_call.h"
#include "server/service/subscribe_senders.h"

namespace mbstream {

namespace {

constexpr int kDefaultBatch = 256;
constexpr int kMaxBatch = 4096;
constexpr auto kQueuedPoll = std::chrono::milliseconds(50);  // a queued run's claim

}  // namespace

void SubscribeCall::Start() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!writes_.conclusion()) {
    const grpc::Status status = Serve([&] { return Accept(); });
    if (!status.ok()) Conclude(status);
  }
  if (phase_ == Phase::kStarting && writes_.conclusion()) phase_ = Phase::kStreaming;  // to end
  Turn(lock);
}

grpc::Status SubscribeCall::Accept() {
  const v1::SubscribeRequest::Start& start = first_.start();
  const bool follow = start.target_case() == v1::SubscribeRequest::Start::kFollow;
  if (!follow && start.run_id().empty()) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        "Subscribe: start.run_id is empty; give a run id or follow = true");
  }
  if (start.max_batch() < 0 || start.max_batch() > kMaxBatch) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        "Subscribe: start.max_batch is " + std::to_string(start.max_batch()) +
                            "; give 0 (the server's choice) up to " + std::to_string(kMaxBatch));
  }
  const int max_batch = start.max_batch() > 0 ? start.max_batch() : kDefaultBatch;
  if (start.has_replay() && follow) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        "Subscribe: start.replay needs a run_id, not follow");
  }
  RunManager& runs = *deps_.runs;
  if (std::optional<ReplayPlan> plan =
          start.has_replay() ? PlanReplay(runs, start) : std::nullopt) {
    v1::ProbeSet set;
    set.set_id(runs.replays().NewProbeSetId());
    set.set_run_id(plan->run.id());
    set.set_viewer(start.replay().viewer());
    set.set_scene(start.replay().scene());
    inbox_.emplace(&runs, set);
    const std::string subscribed = "replay " + plan->run.id();
    Go(NewReplaySender(std::move(*plan), max_batch, start.contacts()), subscribed);
    return grpc::Status::OK;
  }
  // A run of another replica: its owner's stream, relayed (a queued one: looked at again).
  if (!follow && deps_.peers != nullptr && runs.replica().shared_store() &&
      !PeerChannels::IsProxied(*context_)) {
    ReplicaControl::RunPlace place = runs.replica().Locate(start.run_id());
    using Where = ReplicaControl::RunPlace::Where;
    if (place.where == Where::kElsewhere) {
      sender_ = NewRelaySender(*this, std::move(place.info), first_);
      phase_ = Phase::kStreaming;
      return grpc::Status::OK;
    }
    if (place.where == Where::kQueued && !stopping()) {
      deps_.pump->PostAt(Clock::now() + kQueuedPoll,
                         [self = shared_from_this()] { self->Start(); });
      return grpc::Status::OK;
    }
  }
  return AttachHere(follow, max_batch);
}

grpc::Status SubscribeCall::AttachHere(bool follow, int max_batch) {
  RunManager& runs = *deps_.runs;
  std::unique_ptr<FollowRelays> relays;
  if (follow) {
    runs.subscriptions().AttachFollow(subscription_);
    if (deps_.peers != nullptr && runs.replica().shared_store()) {
      relays = std::make_unique<FollowRelays>(
          deps_.peers, &runs, context_,
          [this](const v1::SubscribeEvent& e) { return WriteAndWait(e); }, max_batch,
          first_.start().contacts());
      FollowRelays* raw = relays.get();
      divert_ = {[raw](const v1::SubscribeRequest& r) { return raw->Divert(r); }, {}};
    }
  } else {
    runs.subscriptions().AttachRun(subscription_, first_.start().run_id(), true);
  }
  Go(NewLiveSender(follow, max_batch, first_.start().contacts(), std::move(relays)),
     follow ? "follow" : first_.start().run_id());
  return grpc::Status::OK;
}

void SubscribeCall::Go(std::unique_ptr<SubscribeSender> sender, const std::string& subscribed) {
  sender_ = std::move(sender);
  phase_ = Phase::kStreaming;
  reading_ = true;
  read_wanted_ = true;
  v1::SubscribeEvent event;
  event.set_subscribed(subscribed);
  Enqueue(std::move(event));
}

}  // namespace mbstream
