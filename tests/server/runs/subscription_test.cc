// Subscription: a bounded queue that drops the oldest frames of a slow subscriber and counts
// every dropped frame, in order, before the end of its run.
#include "server/runs/subscription.h"

#include <gtest/gtest.h>

#include <map>

namespace mbstream {
namespace {

StreamEvent Frame(const std::string& run, int64_t seq) {
  auto frame = std::make_shared<v1::Frame>();
  frame->set_seq(seq);
  return {StreamEvent::Kind::kFrame, run, frame};
}

StreamEvent Ended(const std::string& run) { return {StreamEvent::Kind::kRunEnded, run, nullptr}; }

// Pops everything; per run: frames delivered, missed counted, and whether the end came last.
struct Drained {
  std::map<std::string, int64_t> delivered, missed;
  std::map<std::string, bool> ended;
  bool frame_after_end = false;
};

Drained Drain(Subscription& subscription, int max_frames) {
  Drained out;
  std::deque<StreamEvent> events;
  for (;;) {
    events.clear();
    int64_t missed = 0;
    subscription.Pop(std::chrono::milliseconds(0), max_frames, &events, &missed);
    if (events.empty()) return out;
    const std::string& run = events.front().run_id;
    out.missed[run] += missed;
    for (const StreamEvent& e : events) {
      if (e.kind == StreamEvent::Kind::kFrame) {
        ++out.delivered[run];
        if (out.ended[run]) out.frame_after_end = true;
      } else if (e.kind == StreamEvent::Kind::kRunEnded) {
        out.ended[run] = true;
      }
    }
  }
}

TEST(Subscription, EveryFrameOfAFastRunIsDeliveredOrCountedBeforeItsEnd) {
  Subscription subscription(16);
  for (int k = 0; k < 40001; ++k) subscription.Push(Frame("r", k));
  subscription.Push(Ended("r"));
  const Drained drained = Drain(subscription, 1024);
  EXPECT_EQ(drained.delivered.at("r"), 16);
  EXPECT_EQ(drained.delivered.at("r") + drained.missed.at("r"), 40001);
  EXPECT_TRUE(drained.ended.at("r"));
  EXPECT_FALSE(drained.frame_after_end);
  EXPECT_EQ(subscription.missed_total(), 40001 - 16);
}

TEST(Subscription, MissedFramesReachTheConsumerWhenTheNextEventIsTheEnd) {
  // Queue: A0, A-ended, then B frames push A0 out: its count goes with A's end.
  Subscription subscription(1);
  subscription.Push(Frame("A", 0));
  subscription.Push(Ended("A"));
  subscription.Push(Frame("B", 0));
  std::deque<StreamEvent> events;
  int64_t missed = -1;
  ASSERT_TRUE(subscription.Pop(std::chrono::milliseconds(0), 10, &events, &missed));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events.front().kind, StreamEvent::Kind::kRunEnded);
  EXPECT_EQ(events.front().run_id, "A");
  EXPECT_EQ(missed, 1);
  events.clear();
  ASSERT_TRUE(subscription.Pop(std::chrono::milliseconds(0), 10, &events, &missed));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events.front().run_id, "B");
  EXPECT_EQ(missed, 0);
}

TEST(Subscription, MissedFramesOfARunWithNothingQueuedWaitForItsNextEvent) {
  // Two runs at once (two workers): B's frames push out A's only frame; A's next event (its
  // end) carries the count, not B's frames.
  Subscription subscription(2);
  subscription.Push(Frame("A", 0));
  subscription.Push(Frame("B", 0));
  subscription.Push(Frame("B", 1));  // drops A0
  subscription.Push(Frame("B", 2));  // drops B0
  subscription.Push(Ended("A"));
  subscription.Push(Ended("B"));
  const Drained drained = Drain(subscription, 10);
  EXPECT_EQ(drained.missed.at("A"), 1);
  EXPECT_EQ(drained.delivered.count("A"), 0u);
  EXPECT_EQ(drained.missed.at("B"), 1);
  EXPECT_EQ(drained.delivered.at("B"), 2);
  EXPECT_TRUE(drained.ended.at("A") && drained.ended.at("B"));
}

TEST(Subscription, InterleavedRunsKeepTheirOwnCounts) {
  Subscription subscription(8);
  for (int k = 0; k < 1000; ++k) {
    subscription.Push(Frame("A", k));
    if (k % 3 == 0) subscription.Push(Frame("B", k / 3));
  }
  subscription.Push(Ended("B"));
  subscription.Push(Ended("A"));
  const Drained drained = Drain(subscription, 3);
  EXPECT_EQ(drained.delivered.at("A") + drained.missed.at("A"), 1000);
  EXPECT_EQ(drained.delivered.at("B") + drained.missed.at("B"), 334);
  EXPECT_FALSE(drained.frame_after_end);
}

TEST(Subscription, APopThatLosesNothingReportsNoMissedFrames) {
  Subscription subscription(4);
  subscription.Push(Frame("r", 0));
  subscription.Push(Frame("r", 1));
  std::deque<StreamEvent> events;
  int64_t missed = -1;
  ASSERT_TRUE(subscription.Pop(std::chrono::milliseconds(0), 10, &events, &missed));
  EXPECT_EQ(events.size(), 2u);
  EXPECT_EQ(missed, 0);
}

}  // namespace
}  // namespace mbstream
