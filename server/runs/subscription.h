// One subscriber's bounded queue of stream events (fan-out: docs/architecture.md, step 3).
//
// The run's thread pushes; the subscriber's stream handler pops. Pushing never blocks: when
// the queue holds `capacity` frames, the oldest frame is dropped and counted as missed, so a
// slow subscriber gets the newest frames and never slows the run or other subscribers.
// Run-started and run-ended events are never dropped.
//
// Every frame pushed is either popped or counted: a dropped frame's count moves to the next
// queued event of the same run (a frame or the run-ended event), so it reaches the consumer
// in order, before that run's end, whatever kind of event comes next.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/run.pb.h"

namespace mbstream {

struct StreamEvent {
  // kRemoteRun: a run integrating on another replica started (follow subscriptions with a
  // shared store; the stream proxies it from that replica).
  enum class Kind { kRunStarted, kFrame, kRunEnded, kRemoteRun };
  Kind kind = Kind::kFrame;
  std::string run_id;
  std::shared_ptr<const v1::Frame> frame;  // kFrame
  int64_t missed = 0;                      // frames of this run dropped just before this event
};

class Subscription {
 public:
  explicit Subscription(int capacity_frames);

  // Producer side (never blocks).
  void Push(StreamEvent event);
  // No more events will come (the server is shutting down, or a one-run subscription ended).
  void Close();

  // Consumer side: waits up to `timeout` for events, then moves out up to `max_frames` frames
  // of one run (stopping before any non-frame event, which is returned alone). `missed` gets
  // the frames of that run dropped before the events moved out (report it before a non-frame
  // event). Returns false when the queue is closed and empty.
  bool Pop(std::chrono::milliseconds timeout, int max_frames, std::deque<StreamEvent>* out,
           int64_t* missed);

  // Called (under the queue's lock: it must only hand off, never call back) whenever an event
  // is pushed or the queue closes: a consumer that does not wait in Pop is told to pop.
  // Empty: none (again).
  void SetListener(std::function<void()> listener);

  // Set by the consumer when its stream has gone; producers then detach it.
  void Cancel();
  bool cancelled() const;

  int64_t missed_total() const;

 private:
  // Drops the oldest queued frame; its count moves to the next event of its run (mutex_ held).
  void DropOldestFrame();

  const int capacity_frames_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<StreamEvent> events_;
  // Dropped frames whose run has no later event queued yet, by run id.
  std::map<std::string, int64_t> pending_missed_;
  int frames_queued_ = 0;
  int64_t missed_total_ = 0;
  bool closed_ = false;
  bool cancelled_ = false;
  std::function<void()> listener_;
};

}  // namespace mbstream
