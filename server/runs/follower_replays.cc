#include "server/runs/follower_replays.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <exception>
#include <string>
#include <utility>

#include "server/runs/replay_cursor.h"
#include "server/runs/request_error.h"

namespace mbstream {

FollowerReplays::FollowerReplays(const Store* store, RunClock* clock)
    : store_(store), clock_(clock) {}

FollowerReplays::~FollowerReplays() { Stop(); }

void FollowerReplays::Start(const v1::RunInfo& info, double speed_x,
                            std::vector<std::shared_ptr<Subscription>> followers) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (stop_) throw RequestError(RequestErrorKind::kUnavailable, "the server is shutting down");
  if (streaming_ >= kMaxReplays) {
    throw RequestError(RequestErrorKind::kResourceExhausted,
                       "this server already replays " + std::to_string(streaming_) +
                           " runs to its followers, its limit; wait for one to end");
  }
  ++streaming_;
  threads_.emplace_back([this, info, speed_x, followers = std::move(followers)] {
    try {
      Stream(info, speed_x, followers);
    } catch (const std::exception& e) {
      spdlog::error("replay of run {} to the followers: {}", info.id(), e.what());
    }
    std::lock_guard<std::mutex> done(mutex_);
    --streaming_;
  });
}

void FollowerReplays::Stream(const v1::RunInfo& info, double speed_x,
                             const std::vector<std::shared_ptr<Subscription>>& followers) {
  auto push = [&](StreamEvent event) {
    for (const auto& follower : followers) {
      if (!follower->cancelled()) follower->Push(event);
    }
  };
  push({StreamEvent::Kind::kRunStarted, info.id(), nullptr});
  ReplayCursor frames(store_, info.id(), info.frames());
  const RunClock::TimePoint start = clock_->Now();
  const double t0 = frames.At(0).t_s();
  for (int64_t seq = 0; seq < info.frames(); ++seq) {
    auto frame = std::make_shared<const v1::Frame>(frames.At(seq));
    const auto due = start + std::chrono::duration_cast<RunClock::TimePoint::duration>(
                                 std::chrono::duration<double>((frame->t_s() - t0) / speed_x));
    clock_->WaitUntil(due, stop_);
    if (stop_) return;
    push({StreamEvent::Kind::kFrame, info.id(), std::move(frame)});
  }
  push({StreamEvent::Kind::kRunEnded, info.id(), nullptr});
}

void FollowerReplays::Stop() {
  std::vector<std::thread> threads;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    threads.swap(threads_);
  }
  for (std::thread& thread : threads) thread.join();
}

int FollowerReplays::streaming() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return streaming_;
}

}  // namespace mbstream
