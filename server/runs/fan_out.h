// The server's subscriptions (fan-out: docs/architecture.md): how many there are, against
// ServerLimits::max_subscribers, and the follow streams, which get every run that starts here
// exactly once (a run started before a follower came is attached by Follow, one started
// after by AnnounceStart, never both) and the runs other replicas claim (AnnounceRemote).
// The frames of one run go to its subscribers through the Run (Run::Attach, Run::Publish).
// Thread-safe.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "server/runs/run.h"
#include "server/runs/subscription.h"

namespace mbstream {

class FanOut {
 public:
  // Each new subscription queues up to `queue_frames` frames (ServerLimits).
  FanOut(int max_subscribers, int queue_frames);

  // A subscription counted from now until Unsubscribe, attached to something or not. Throws
  // RequestError(kResourceExhausted) at max_subscribers.
  std::shared_ptr<Subscription> NewSubscription();
  // Cancels it, stops following if it followed, and counts it no more.
  void Unsubscribe(const std::shared_ptr<Subscription>& subscriber);
  int subscriber_count() const;

  // `follower` gets every run that starts from now on; and, in the same step, the run
  // `running()` returns (the one running now, or nullptr). Returns whether there was one.
  bool Follow(const std::shared_ptr<Subscription>& follower,
              const std::function<std::shared_ptr<Run>()>& running);
  // Run `run` starts: `start` (which marks it running) is called, then every follower is
  // attached to it (with its started event), in one step with Follow.
  void AnnounceStart(Run& run, const std::function<void()>& start);
  // A run of another replica started (kRemoteRun to each follower).
  void AnnounceRemote(const std::string& run_id);
  bool has_followers() const;
  std::vector<std::shared_ptr<Subscription>> followers() const;  // a copy

 private:
  const int max_subscribers_;
  const int queue_frames_;
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<Subscription>> followers_;
  int subscribers_ = 0;
};

}  // namespace mbstream
