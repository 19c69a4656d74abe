// Run::Publish: the latest frame and the fan-out, without an allocation per frame while
// nobody subscribes (the frame's storage goes back and forth between the run and its worker).
#include <chrono>
#include <deque>
#include <memory>

#include <gtest/gtest.h>

#include "server/runs/run.h"
#include "tests/common/allocation_counter.h"

namespace mbstream {
namespace {

// Fills `frame` in place, as FrameToProto does.
void Fill(int64_t seq, v1::Frame* frame) {
  frame->set_seq(seq);
  frame->set_t_s(0.05 * static_cast<double>(seq));
  frame->mutable_q()->Resize(6, 0.0);
  frame->mutable_qd()->Resize(6, 0.0);
  for (int j = 0; j < 6; ++j) {
    frame->set_q(j, 0.1 * j + 1e-3 * static_cast<double>(seq));
    frame->set_qd(j, -0.2 * j);
  }
  frame->mutable_tcp_m()->set_x(0.5 + 1e-3 * static_cast<double>(seq));
}

std::shared_ptr<Run> MakeRun() {
  v1::RunInfo info;
  info.set_id("r-1");
  return std::make_shared<Run>(info, RunConfig{}, std::make_shared<CompiledModel>());
}

TEST(RunPublishTest, NoAllocationPerFrameWithoutSubscribers) {
  auto run = MakeRun();
  EXPECT_EQ(run->latest_frame(), nullptr);
  v1::Frame frame;
  for (int64_t seq = 0; seq < 2; ++seq) {  // both messages' fields get their storage
    Fill(seq, &frame);
    run->Publish(&frame);
  }
  const long before = testing::AllocationCount();
  for (int64_t seq = 2; seq < 1000; ++seq) {
    Fill(seq, &frame);
    run->Publish(&frame);
  }
  EXPECT_EQ(testing::AllocationCount(), before);
  const auto latest = run->latest_frame();
  ASSERT_NE(latest, nullptr);
  v1::Frame want;
  Fill(999, &want);
  EXPECT_EQ(latest->SerializeAsString(), want.SerializeAsString());
  EXPECT_EQ(run->Info().frames(), 1000);
  EXPECT_DOUBLE_EQ(run->Info().t_s(), 0.05 * 999);
}

TEST(RunPublishTest, SubscribersGetTheLatestThenEveryFrame) {
  auto run = MakeRun();
  v1::Frame frame;
  for (int64_t seq = 0; seq < 3; ++seq) {
    Fill(seq, &frame);
    run->Publish(&frame);
  }
  auto subscriber = std::make_shared<Subscription>(100);
  run->Attach(subscriber, false);
  for (int64_t seq = 3; seq < 6; ++seq) {
    Fill(seq, &frame);
    run->Publish(&frame);
  }
  run->End();
  std::deque<StreamEvent> events;
  int64_t missed = 0;
  ASSERT_TRUE(subscriber->Pop(std::chrono::milliseconds(0), 100, &events, &missed));
  ASSERT_EQ(events.size(), 4u);  // frame 2 (the latest when it attached), 3, 4, 5
  for (std::size_t i = 0; i < events.size(); ++i) {
    v1::Frame want;
    Fill(static_cast<int64_t>(i) + 2, &want);
    ASSERT_NE(events[i].frame, nullptr);
    EXPECT_EQ(events[i].frame->SerializeAsString(), want.SerializeAsString()) << "event " << i;
  }
  EXPECT_EQ(missed, 0);
}

}  // namespace
}  // namespace mbstream
