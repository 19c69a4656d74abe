// Replays of ended runs to the follow streams (ReplayRun: RunReplays::ToFollowers): each
// on a thread of its own, the run's stored frames read one chunk at a time (ReplayCursor) and
// pushed to the followers attached when it started (started, frames paced at `speed_x`
// simulated s per s of the run clock, ended), as if the run were running. At most
// kMaxReplays at once; Stop ends them at once and joins their threads. Thread-safe.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "mbstream/v1/run.pb.h"
#include "server/runs/run_clock.h"
#include "server/runs/subscription.h"

namespace mbstream {

class Store;

class FollowerReplays {
 public:
  static constexpr int kMaxReplays = 4;  // streaming at the same time

  // `store` and `clock` must outlive the replays.
  FollowerReplays(const Store* store, RunClock* clock);
  ~FollowerReplays();  // Stop()
  FollowerReplays(const FollowerReplays&) = delete;
  FollowerReplays& operator=(const FollowerReplays&) = delete;

  // Streams the ended run `info` (its frames stored, info.frames() > 0) to `followers` on a
  // new thread; returns at once. Throws RequestError: kUnavailable after Stop,
  // kResourceExhausted when kMaxReplays stream already.
  void Start(const v1::RunInfo& info, double speed_x,
             std::vector<std::shared_ptr<Subscription>> followers);
  // Ends every replay (a follower gets no run-ended event then) and joins their threads;
  // later Starts are refused. Idempotent.
  void Stop();
  int streaming() const;  // replays started and not yet ended

 private:
  void Stream(const v1::RunInfo& info, double speed_x,
              const std::vector<std::shared_ptr<Subscription>>& followers);

  const Store* const store_;
  RunClock* const clock_;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;
  std::vector<std::thread> threads_;  // joined by Stop
  int streaming_ = 0;
};

}  // namespace mbstream
