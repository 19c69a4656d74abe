#include "server/service/follow_relays.h"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace mbstream {

FollowRelays::FollowRelays(PeerChannels* peers, const RunManager* runs,
                           const grpc::ServerContextBase* context,
                           std::function<bool(const v1::SubscribeEvent&)> write, int max_batch,
                           bool contacts)
    : peers_(peers),
      runs_(runs),
      context_(context),
      write_(std::move(write)),
      max_batch_(max_batch),
      contacts_(contacts) {}

FollowRelays::~FollowRelays() { Stop(); }

void FollowRelays::Open(const std::string& run_id) {
  ReplicaControl::RunPlace place;
  try {
    place = runs_->replica().Locate(run_id);
  } catch (const std::exception& error) {
    spdlog::warn("follow: run {} of another replica: {}", run_id, error.what());
    return;
  }
  if (place.where != ReplicaControl::RunPlace::Where::kElsewhere) return;  // ended already
  std::lock_guard<std::mutex> lock(mutex_);
  if (stopped_) return;
  // Relays that ended leave (their threads have returned or are returning).
  for (auto it = relays_.begin(); it != relays_.end();) {
    if ((*it)->done) {
      (*it)->thread.join();
      it = relays_.erase(it);
    } else {
      ++it;
    }
  }
  // A run announced twice (at attach and by the cluster's next look) is relayed once.
  for (const auto& open : relays_) {
    if (open->run_id == run_id) return;
  }
  auto relay = std::make_shared<Relay>();
  relay->run_id = run_id;
  Relay* raw = relay.get();
  relay->thread = std::thread([this, raw, owner = std::move(place.info)] { Pass(raw, owner); });
  relays_.push_back(std::move(relay));
}

void FollowRelays::Pass(Relay* relay, const v1::RunInfo& owner) {
  v1::SubscribeRequest start;
  start.mutable_start()->set_run_id(relay->run_id);
  start.mutable_start()->set_max_batch(max_batch_);
  start.mutable_start()->set_contacts(contacts_);
  PeerSubscribe* upstream = nullptr;
  try {
    auto connected = std::make_unique<PeerSubscribe>(*peers_, *context_, owner, start);
    std::lock_guard<std::mutex> lock(mutex_);
    if (!stopped_) {
      relay->upstream = std::move(connected);
      upstream = relay->upstream.get();
    }
  } catch (const std::exception& error) {
    spdlog::warn("follow: {}", error.what());
  }
  if (upstream != nullptr) {
    bool ended = false;
    v1::SubscribeEvent event;
    while (upstream->Read(&event)) {
      // The owner's `subscribed` and `closing` are its stream's own business.
      if (event.has_subscribed() || event.has_closing()) continue;
      if (!write_(event)) {
        upstream->Cancel();
        break;
      }
      if (event.has_run_ended()) {  // its last probes came before: the owner waited for them
        ended = true;
        upstream->WritesDone();
      }
    }
    const grpc::Status status = upstream->Finish();
    if (!ended && !status.ok() && status.error_code() != grpc::StatusCode::CANCELLED) {
      spdlog::warn("follow: relay of run {} ended: {}", relay->run_id, status.error_message());
    }
  }
  relay->done = true;
}

bool FollowRelays::Divert(const v1::SubscribeRequest& request) {
  if (!request.has_probe()) return false;
  std::shared_ptr<Relay> relay;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto found = std::find_if(relays_.begin(), relays_.end(),
                              [&](const auto& r) { return r->run_id == request.probe().run_id(); });
    if (found == relays_.end()) return false;
    relay = *found;
    if (!relay->upstream || relay->done) return true;  // not connected yet, or ended: dropped
  }
  (void)relay->upstream->Write(request);  // Stop joins the thread, never frees `upstream` early
  return true;
}

void FollowRelays::Stop() {
  std::vector<std::shared_ptr<Relay>> relays;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
    for (const auto& relay : relays_) {
      if (relay->upstream) relay->upstream->Cancel();
    }
    relays.swap(relays_);
  }
  for (const auto& relay : relays) relay->thread.join();
}

}  // namespace mbstream
