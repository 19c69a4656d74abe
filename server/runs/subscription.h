// One subscriber's bounded queue of stream events (fan-out, design.md section 1).
//
// The run's thread pushes; the subscriber's stream handler pops. Pushing never blocks: when
// the queue holds `capacity` frames, the oldest frame is dropped and counted as missed, so a
// slow subscriber gets the newest frames and never slows the run or other subscribers.
// Run-started and run-ended events are never dropped.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/run.pb.h"

namespace mbstream {

struct StreamEvent {
  enum class Kind { kRunStarted, kFrame, kRunEnded };
  Kind kind = Kind::kFrame;
  std::string run_id;
  std::shared_ptr<const v1::Frame> frame;  // kFrame
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
  // the frames dropped since the last Pop. Returns false when the queue is closed and empty.
  bool Pop(std::chrono::milliseconds timeout, int max_frames, std::deque<StreamEvent>* out,
           int64_t* missed);

  // Set by the consumer when its stream has gone; producers then detach it.
  void Cancel();
  bool cancelled() const;

  int64_t missed_total() const;

 private:
  const int capacity_frames_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<StreamEvent> events_;
  int frames_queued_ = 0;
  int64_t missed_ = 0;
  int64_t missed_total_ = 0;
  bool closed_ = false;
  bool cancelled_ = false;
};

}  // namespace mbstream
