#include "server/runs/subscription.h"

#include <algorithm>

#include "shared/common/check.h"

namespace mbstream {

Subscription::Subscription(int capacity_frames) : capacity_frames_(capacity_frames) {
  MBSTREAM_CHECK(capacity_frames_ > 0);
}

void Subscription::Push(StreamEvent event) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_ || cancelled_) return;
    if (event.kind == StreamEvent::Kind::kFrame) {
      if (frames_queued_ == capacity_frames_) DropOldestFrame();
      ++frames_queued_;
    }
    if (auto pending = pending_missed_.find(event.run_id); pending != pending_missed_.end()) {
      event.missed += pending->second;
      pending_missed_.erase(pending);
    }
    events_.push_back(std::move(event));
    if (listener_) listener_();
  }
  ready_.notify_one();
}

void Subscription::DropOldestFrame() {
  auto oldest = std::find_if(events_.begin(), events_.end(), [](const StreamEvent& e) {
    return e.kind == StreamEvent::Kind::kFrame;
  });
  MBSTREAM_CHECK(oldest != events_.end());
  const int64_t dropped = 1 + oldest->missed;
  const std::string run_id = std::move(oldest->run_id);
  auto next = events_.erase(oldest);
  --frames_queued_;
  missed_total_ += 1;
  next =
      std::find_if(next, events_.end(), [&](const StreamEvent& e) { return e.run_id == run_id; });
  if (next != events_.end()) {
    next->missed += dropped;
  } else {
    pending_missed_[run_id] += dropped;
  }
}

void Subscription::Close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    if (listener_) listener_();
  }
  ready_.notify_all();
}

void Subscription::Cancel() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    cancelled_ = true;
    events_.clear();
    frames_queued_ = 0;
    pending_missed_.clear();
  }
  ready_.notify_all();
}

void Subscription::SetListener(std::function<void()> listener) {
  std::lock_guard<std::mutex> lock(mutex_);
  listener_ = std::move(listener);
}

bool Subscription::cancelled() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return cancelled_;
}

int64_t Subscription::missed_total() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return missed_total_;
}

bool Subscription::Pop(std::chrono::milliseconds timeout, int max_frames,
                       std::deque<StreamEvent>* out, int64_t* missed) {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait_for(lock, timeout, [&] { return !events_.empty() || closed_ || cancelled_; });
  *missed = 0;
  if (events_.empty()) return !(closed_ || cancelled_);
  if (events_.front().kind != StreamEvent::Kind::kFrame) {
    *missed = events_.front().missed;
    out->push_back(std::move(events_.front()));
    events_.pop_front();
    return true;
  }
  const std::string run_id = events_.front().run_id;
  int taken = 0;
  while (!events_.empty() && taken < max_frames &&
         events_.front().kind == StreamEvent::Kind::kFrame && events_.front().run_id == run_id) {
    *missed += events_.front().missed;
    out->push_back(std::move(events_.front()));
    events_.pop_front();
    --frames_queued_;
    ++taken;
  }
  return true;
}

}  // namespace mbstream
