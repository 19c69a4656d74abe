// Building FrameBatch messages from a subscription's events.
#pragma once

#include <deque>

#include "mbstream/v1/frame.pb.h"
#include "server/runs/subscription.h"
#include "server/service/sent_frames.h"

namespace mbstream {

// Moves the frame events of `events` (all of one run) into `batch`, with `missed`; a batch
// of no frames only reports `missed` (before a run-ended event). Records each frame's send
// time in `sent` when given.
// `contacts`: the frames keep their contacts (SubscribeRequest.Start.contacts); false: they go
// without.
inline void FillFrameBatch(std::deque<StreamEvent>& events, int64_t missed, v1::FrameBatch* batch,
                           SentFrames* sent = nullptr, bool contacts = false) {
  batch->Clear();
  batch->set_run_id(events.front().run_id);
  batch->set_missed(missed);
  const SentFrames::Clock::time_point now = SentFrames::Clock::now();
  for (const StreamEvent& event : events) {
    if (event.kind != StreamEvent::Kind::kFrame) continue;
    v1::Frame* frame = batch->add_frames();
    *frame = *event.frame;
    if (!contacts) frame->clear_contacts();
    if (sent) sent->Record(event.run_id, event.frame->seq(), event.frame->t_s(), now);
  }
}

}  // namespace mbstream
