// FollowerReplays: a stored run goes to the followers paced by the (manual) run clock, from
// its started event to its ended one; a fifth replay at once is refused, Stop ends them all.
#include "server/runs/follower_replays.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <deque>
#include <filesystem>
#include <string>
#include <vector>

#include "server/runs/request_error.h"
#include "server/store/store.h"
#include "tests/server/runs/manual_run_clock.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;

class FollowerReplaysTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mbstream-follower-replays-" + std::to_string(getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    store_ = Store::Open(dir_.string());
    info_.set_id("r-1");
    info_.set_state(v1::FINISHED);
    std::vector<v1::Frame> frames(4);
    for (int seq = 0; seq < 4; ++seq) {
      frames[seq].set_seq(seq);
      frames[seq].set_t_s(0.1 * seq);  // paced at 2x: one frame every 50 ms
    }
    info_.set_frames(4);
    store_->PutRun(info_);
    store_->FinishRun(info_, frames);
  }
  void TearDown() override {
    store_.reset();
    fs::remove_all(dir_);
  }

  // The next event (waits up to 30 s: a failure then).
  static StreamEvent Next(Subscription& follower) {
    std::deque<StreamEvent> events;
    int64_t missed = 0;
    if (!follower.Pop(std::chrono::seconds(30), 1, &events, &missed) || events.empty()) {
      ADD_FAILURE() << "no event";
      return {};
    }
    return events.front();
  }

  fs::path dir_;
  std::unique_ptr<Store> store_;
  v1::RunInfo info_;
  testing::ManualRunClock clock_;
};

TEST_F(FollowerReplaysTest, StreamsTheStoredFramesPacedByTheClockThenTheEnd) {
  FollowerReplays replays(store_.get(), &clock_);
  auto follower = std::make_shared<Subscription>(64);
  replays.Start(info_, 2.0, {follower});
  EXPECT_EQ(Next(*follower).kind, StreamEvent::Kind::kRunStarted);
  const RunClock::TimePoint start = clock_.Now();
  for (int64_t seq = 0; seq < 4; ++seq) {
    if (seq > 0) {  // frame seq waits for start + 0.1 seq / 2 s
      const std::optional<RunClock::TimePoint> due = clock_.WaitForWaiter();
      ASSERT_TRUE(due.has_value()) << "frame " << seq;
      EXPECT_EQ(*due - start, milliseconds(50 * seq)) << "frame " << seq;
      clock_.Advance(milliseconds(50));
    }
    const StreamEvent frame = Next(*follower);
    ASSERT_EQ(frame.kind, StreamEvent::Kind::kFrame);
    EXPECT_EQ(frame.frame->seq(), seq);
  }
  EXPECT_EQ(Next(*follower).kind, StreamEvent::Kind::kRunEnded);
  replays.Stop();
  EXPECT_EQ(replays.streaming(), 0);
}

TEST_F(FollowerReplaysTest, AFifthReplayAtOnceIsRefusedAndStopEndsThemAll) {
  FollowerReplays replays(store_.get(), &clock_);
  std::vector<std::shared_ptr<Subscription>> followers;
  for (int i = 0; i < FollowerReplays::kMaxReplays; ++i) {
    followers.push_back(std::make_shared<Subscription>(64));
    replays.Start(info_, 1.0, {followers.back()});
  }
  for (const auto& follower : followers) {  // each then waits for frame 1's time
    EXPECT_EQ(Next(*follower).kind, StreamEvent::Kind::kRunStarted);
    EXPECT_EQ(Next(*follower).kind, StreamEvent::Kind::kFrame);  // frame 0, due at once
  }
  EXPECT_EQ(replays.streaming(), FollowerReplays::kMaxReplays);
  try {
    replays.Start(info_, 1.0, {});
    ADD_FAILURE() << "a fifth replay was started";
  } catch (const RequestError& e) {
    EXPECT_EQ(e.kind(), RequestErrorKind::kResourceExhausted);
    EXPECT_STREQ(e.what(),
                 "this server already replays 4 runs to its followers, its limit; wait for one to "
                 "end");
  }
  replays.Stop();  // the clock never reaches frame 1's time: Stop ends them
  EXPECT_EQ(replays.streaming(), 0);
  for (const auto& follower : followers) {  // no run-ended event: the replay was cut short
    std::deque<StreamEvent> events;
    int64_t missed = 0;
    follower->Pop(milliseconds(0), 1, &events, &missed);
    EXPECT_TRUE(events.empty());
  }
  try {
    replays.Start(info_, 1.0, {});
    ADD_FAILURE() << "a replay was started after Stop";
  } catch (const RequestError& e) {
    EXPECT_EQ(e.kind(), RequestErrorKind::kUnavailable);
  }
}

}  // namespace
}  // namespace mbstream
