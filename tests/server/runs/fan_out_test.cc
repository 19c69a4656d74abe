// FanOut: subscriptions count against their limit until unsubscribed; a follower gets each
// run that starts here exactly once, whether it started before the follower came or after,
// and the runs of other replicas; an unsubscribed follower gets nothing more.
#include "server/runs/fan_out.h"

#include <gtest/gtest.h>

#include <deque>
#include <string>
#include <vector>

#include "server/runs/request_error.h"

namespace mbstream {
namespace {

std::shared_ptr<Run> MakeRun(const std::string& id) {
  v1::RunInfo info;
  info.set_id(id);
  return std::make_shared<Run>(info, RunConfig{}, std::make_shared<CompiledModel>());
}

// The events queued now, as "kind:run" strings (no wait: they are pushed synchronously).
std::vector<std::string> Queued(Subscription& subscription) {
  std::vector<std::string> out;
  std::deque<StreamEvent> events;
  int64_t missed = 0;
  while (subscription.Pop(std::chrono::milliseconds(0), 16, &events, &missed) && !events.empty()) {
    for (const StreamEvent& event : events) {
      const char* kind = event.kind == StreamEvent::Kind::kRunStarted  ? "started"
                         : event.kind == StreamEvent::Kind::kRemoteRun ? "remote"
                         : event.kind == StreamEvent::Kind::kRunEnded  ? "ended"
                                                                       : "frame";
      out.push_back(std::string(kind) + ":" + event.run_id);
    }
    events.clear();
  }
  return out;
}

TEST(FanOutTest, ASubscriptionPastTheLimitIsRefusedUntilOneIsGone) {
  FanOut fan_out(2, 16);
  auto first = fan_out.NewSubscription();
  auto second = fan_out.NewSubscription();
  try {
    fan_out.NewSubscription();
    ADD_FAILURE() << "a third subscription was counted";
  } catch (const RequestError& e) {
    EXPECT_EQ(e.kind(), RequestErrorKind::kResourceExhausted);
    EXPECT_STREQ(e.what(),
                 "this server already has 2 subscribers, its limit; close a viewer or watcher "
                 "and retry");
  }
  fan_out.Unsubscribe(first);
  EXPECT_TRUE(first->cancelled());
  EXPECT_EQ(fan_out.subscriber_count(), 1);
  EXPECT_NE(fan_out.NewSubscription(), nullptr);
  EXPECT_EQ(fan_out.subscriber_count(), 2);
}

TEST(FanOutTest, AFollowerGetsEachRunOnceWhetherItStartedBeforeOrAfter) {
  FanOut fan_out(10, 16);
  const auto before = MakeRun("r-before");
  const auto after = MakeRun("r-after");
  auto follower = fan_out.NewSubscription();
  EXPECT_TRUE(fan_out.Follow(follower, [&] { return before; }));
  // The run the follower was attached to, announced again (its worker marking it running
  // too): attached once only.
  fan_out.AnnounceStart(*before, [] {});
  int started = 0;
  fan_out.AnnounceStart(*after, [&] { ++started; });
  EXPECT_EQ(started, 1);
  fan_out.AnnounceRemote("r-elsewhere");
  EXPECT_EQ(Queued(*follower), (std::vector<std::string>{"started:r-before", "started:r-after",
                                                         "remote:r-elsewhere"}));
  EXPECT_TRUE(fan_out.has_followers());
  EXPECT_EQ(fan_out.followers().size(), 1u);
}

TEST(FanOutTest, OnlyFollowersAreAnnouncedAndAnUnsubscribedOneGetsNothingMore) {
  FanOut fan_out(10, 16);
  auto plain = fan_out.NewSubscription();  // a one-run subscription: not a follower
  auto follower = fan_out.NewSubscription();
  EXPECT_FALSE(fan_out.Follow(follower, [] { return std::shared_ptr<mbstream::Run>(); }));
  fan_out.Unsubscribe(follower);
  EXPECT_FALSE(fan_out.has_followers());
  const auto run = MakeRun("r-1");
  fan_out.AnnounceStart(*run, [] {});
  fan_out.AnnounceRemote("r-2");
  EXPECT_TRUE(Queued(*plain).empty());
  EXPECT_TRUE(Queued(*follower).empty());
  EXPECT_EQ(run->subscriber_count(), 0);
}

}  // namespace
}  // namespace mbstream
