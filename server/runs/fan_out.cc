#include "server/runs/fan_out.h"

#include <algorithm>

#include "server/runs/request_error.h"

namespace mbstream {

FanOut::FanOut(int max_subscribers, int queue_frames)
    : max_subscribers_(max_subscribers), queue_frames_(queue_frames) {}

std::shared_ptr<Subscription> FanOut::NewSubscription() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (subscribers_ >= max_subscribers_) {
      throw RequestError(RequestErrorKind::kResourceExhausted,
                         "this server already has " + std::to_string(subscribers_) +
                             " subscribers, its limit; close a viewer or watcher and retry");
    }
    ++subscribers_;
  }
  return std::make_shared<Subscription>(queue_frames_);
}

void FanOut::Unsubscribe(const std::shared_ptr<Subscription>& subscriber) {
  subscriber->Cancel();
  std::lock_guard<std::mutex> lock(mutex_);
  followers_.erase(std::remove(followers_.begin(), followers_.end(), subscriber), followers_.end());
  --subscribers_;
}

int FanOut::subscriber_count() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return subscribers_;
}

bool FanOut::Follow(const std::shared_ptr<Subscription>& follower,
                    const std::function<std::shared_ptr<Run>()>& running) {
  std::lock_guard<std::mutex> lock(mutex_);
  followers_.push_back(follower);
  const std::shared_ptr<Run> run = running();
  if (run) run->Attach(follower, true);
  return run != nullptr;
}

void FanOut::AnnounceStart(Run& run, const std::function<void()>& start) {
  std::lock_guard<std::mutex> lock(mutex_);
  start();
  followers_.erase(std::remove_if(followers_.begin(), followers_.end(),
                                  [](const auto& f) { return f->cancelled(); }),
                   followers_.end());
  for (const auto& follower : followers_) run.Attach(follower, true);
}

void FanOut::AnnounceRemote(const std::string& run_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& follower : followers_) {
    follower->Push({StreamEvent::Kind::kRemoteRun, run_id, nullptr});
  }
}

bool FanOut::has_followers() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return !followers_.empty();
}

std::vector<std::shared_ptr<Subscription>> FanOut::followers() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return followers_;
}

}  // namespace mbstream
