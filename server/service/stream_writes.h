// The write side of a streaming reactor (subscribe_call.h, watch_call.h): events queued and
// written one at a time (gRPC allows one write in flight), the status the stream ends with
// once they are written, and the writes another thread waits for (a relay's). Not
// thread-safe: every member is used under its reactor's lock.
#pragma once

#include <grpcpp/support/status.h>

#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <utility>

namespace mbstream {

template <typename Event>
class StreamWrites {
 public:
  void Enqueue(Event event, bool* written = nullptr, bool* done = nullptr) {
    queue_.push_back(Outgoing{std::move(event), written, done});
  }
  // The event to write now (it stays queued, at a stable address, until Written), or null
  // when one is being written or none is queued.
  const Event* Next() {
    if (writing_ || queue_.empty()) return nullptr;
    writing_ = true;
    return &queue_.front().event;
  }
  // The write Next gave completed; a failure ends the stream with `gone` (unless it ends
  // otherwise than OK already). Waiters are told through `waiters`.
  void Written(bool ok, const grpc::Status& gone, std::condition_variable& waiters) {
    writing_ = false;
    Outgoing& done = queue_.front();
    if (done.done != nullptr) {
      *done.written = ok;
      *done.done = true;
      waiters.notify_all();
    }
    queue_.pop_front();
    if (!ok && (!conclusion_ || conclusion_->ok())) conclusion_ = gone;
  }
  bool idle() const { return !writing_ && queue_.empty(); }  // nothing queued or being written
  // Whether the stream may finish now: it was concluded, is idle, and no thread is about to
  // start a gRPC operation (OutsideLock).
  bool may_finish() const { return conclusion_ && idle() && outside_lock_ == 0; }

  // Calls `start` (gRPC's StartRead, StartWrite: never with the reactor's lock held, as gRPC
  // may run a reaction inline) with `lock` released; meanwhile the stream may not finish
  // (and be freed by gRPC).
  template <typename Start>
  void OutsideLock(std::unique_lock<std::mutex>& lock, Start start) {
    ++outside_lock_;
    lock.unlock();
    start();
    lock.lock();
    --outside_lock_;
  }

  void Conclude(const grpc::Status& status) {  // the first status given stays
    if (!conclusion_) conclusion_ = status;
  }
  const std::optional<grpc::Status>& conclusion() const { return conclusion_; }

 private:
  struct Outgoing {
    Event event;
    bool* written = nullptr;  // a waiting writer's: set (with `done`) when written
    bool* done = nullptr;
  };
  std::deque<Outgoing> queue_;
  bool writing_ = false;
  int outside_lock_ = 0;  // threads in OutsideLock
  std::optional<grpc::Status> conclusion_;
};

}  // namespace mbstream
