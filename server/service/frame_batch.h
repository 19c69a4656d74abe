// Building FrameBatch messages from a subscription's events.
#pragma once

#include <deque>

#include "mbstream/v1/frame.pb.h"
#include "server/runs/subscription.h"
#include "server/service/sent_times.h"

namespace mbstream {

// Moves the frame events of `events` (all of one run) into `batch`, with `missed`.
// Records each frame's send time in `sent` when given.
inline void FillFrameBatch(std::deque<StreamEvent>& events, int64_t missed, v1::FrameBatch* batch,
                           SentTimes* sent = nullptr) {
  batch->Clear();
  batch->set_run_id(events.front().run_id);
  batch->set_missed(missed);
  const SentTimes::Clock::time_point now = SentTimes::Clock::now();
  for (const StreamEvent& event : events) {
    *batch->add_frames() = *event.frame;
    if (sent) sent->Record(event.run_id, event.frame->seq(), now);
  }
}

}  // namespace mbstream
