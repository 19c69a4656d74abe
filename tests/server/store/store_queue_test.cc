// Store: the run queue of several replicas (run_lease.h), on both backends. Times are
// explicit Unix milliseconds: no sleeps, no wall clock.
#include <set>
#include <thread>

#include <gmock/gmock.h>

#include "server/store/frame_chunks.h"
#include "server/store/store.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;
using testing::MakeFrames;
using testing::MakeRun;

class StoreQueueTest : public testing::StoreBackendTest {
 protected:
  static RunLease Lease(const std::string& replica, int64_t now_ms, int64_t timeout_ms = 10000) {
    return {replica, replica + ".example:50051", now_ms, now_ms + timeout_ms};
  }
  static v1::RunInfo Queued(const std::string& id, int64_t created_ms, int retries = 0) {
    v1::RunInfo info = MakeRun(id, v1::QUEUED, created_ms);
    info.set_started_unix_ms(0);
    info.clear_stats();
    info.mutable_spec()->set_retries(retries);
    return info;
  }
};
INSTANTIATE_STORE_BACKENDS(StoreQueueTest);

TEST_P(StoreQueueTest, ClaimsTheOldestQueuedRunOnceAndRecordsTheReplica) {
  auto store = Open();
  store->PutRun(Queued("r-new", 2000));
  store->PutRun(Queued("r-old", 1000));
  store->PutRun(MakeRun("r-done", v1::FINISHED, 500));
  const auto first = store->ClaimQueuedRun(Lease("a", 5000));
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->id(), "r-old");
  EXPECT_EQ(first->state(), v1::RUNNING);
  EXPECT_EQ(first->replica(), "a");
  EXPECT_EQ(first->replica_address(), "a.example:50051");
  EXPECT_EQ(first->attempts(), 1);
  EXPECT_EQ(first->started_unix_ms(), 5000);
  EXPECT_TRUE(testing::Same(*store->GetRun("r-old"), *first));
  const auto second = store->ClaimQueuedRun(Lease("b", 5001));
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(second->id(), "r-new");
  EXPECT_EQ(second->replica(), "b");
  EXPECT_FALSE(store->ClaimQueuedRun(Lease("a", 5002)).has_value());
}

// What follow streams read (cluster_follow.h): the RUNNING runs only, oldest claim first.
TEST_P(StoreQueueTest, ListsTheRunningRunsInClaimOrder) {
  auto store = Open();
  EXPECT_TRUE(store->ListRunningRuns().empty());
  store->PutRun(Queued("r-1", 1000));
  store->PutRun(Queued("r-2", 2000));
  store->PutRun(Queued("r-3", 3000));
  store->PutRun(MakeRun("r-done", v1::FINISHED, 500));
  ASSERT_TRUE(store->ClaimQueuedRun(Lease("a", 5000)).has_value());
  ASSERT_TRUE(store->ClaimQueuedRun(Lease("b", 5001)).has_value());
  const std::vector<v1::RunInfo> running = store->ListRunningRuns();
  ASSERT_EQ(running.size(), 2u);
  EXPECT_EQ(running[0].id(), "r-1");
  EXPECT_EQ(running[0].replica(), "a");
  EXPECT_EQ(running[1].id(), "r-2");
  EXPECT_EQ(running[1].replica(), "b");
}

// Two replicas (two connections) claiming as fast as they can: every run exactly once.
TEST_P(StoreQueueTest, ConcurrentClaimsNeverTakeOneRunTwice) {
  constexpr int kRuns = 40;
  {
    auto store = Open();
    for (int i = 0; i < kRuns; ++i) store->PutRun(Queued("r-" + std::to_string(i), 1000 + i));
  }
  auto store_a = Open();
  auto store_b = Open();
  std::vector<std::string> claimed_a, claimed_b;
  auto claim_all = [](Store* store, const std::string& replica, std::vector<std::string>* ids) {
    while (auto run = store->ClaimQueuedRun(Lease(replica, 5000))) ids->push_back(run->id());
  };
  std::thread a(claim_all, store_a.get(), "a", &claimed_a);
  std::thread b(claim_all, store_b.get(), "b", &claimed_b);
  a.join();
  b.join();
  std::set<std::string> all(claimed_a.begin(), claimed_a.end());
  all.insert(claimed_b.begin(), claimed_b.end());
  EXPECT_EQ(all.size(), static_cast<size_t>(kRuns));
  EXPECT_EQ(claimed_a.size() + claimed_b.size(), static_cast<size_t>(kRuns));
  for (const std::string& id : claimed_a) EXPECT_EQ(store_a->GetRun(id)->replica(), "a");
  for (const std::string& id : claimed_b) EXPECT_EQ(store_a->GetRun(id)->replica(), "b");
}

TEST_P(StoreQueueTest, RenewedLeaseDoesNotExpireAndAnExpiredOneIsInterruptedWithItsFrames) {
  auto store = Open();
  store->PutRun(Queued("r-1", 1000));
  const v1::RunInfo claimed = *store->ClaimQueuedRun(Lease("a", 5000));  // until 15000
  store->PutFrameChunk("r-1", 0, EncodeFrameChunks(MakeFrames(7, 2)).front(), "");
  EXPECT_TRUE(store->ReapExpiredLeases(14999, "b").empty());
  EXPECT_TRUE(store->RenewLease("r-1", LeaseHolder(claimed), 25000));
  EXPECT_TRUE(store->ReapExpiredLeases(24999, "b").empty());
  EXPECT_EQ(store->GetRun("r-1")->state(), v1::RUNNING);

  const std::vector<v1::RunInfo> reaped = store->ReapExpiredLeases(25001, "b");
  ASSERT_EQ(reaped.size(), 1u);
  EXPECT_EQ(reaped[0].state(), v1::INTERRUPTED);
  EXPECT_EQ(reaped[0].ended_unix_ms(), 25001);
  EXPECT_THAT(reaped[0].message(), HasSubstr("replica a (a.example:50051) stopped renewing"));
  EXPECT_THAT(reaped[0].message(), HasSubstr("replica b marked it INTERRUPTED"));
  EXPECT_TRUE(testing::Same(*store->GetRun("r-1"), reaped[0]));
  EXPECT_EQ(store->GetFrames("r-1").size(), 7u);  // the frames so far are kept
  // The old holder finds its lease gone: it must stop and write nothing.
  EXPECT_FALSE(store->RenewLease("r-1", LeaseHolder(claimed), 35000));
  v1::RunInfo late = claimed;
  late.set_state(v1::FINISHED);
  EXPECT_FALSE(store->PutRunIfHeld(late, LeaseHolder(claimed)));
  EXPECT_EQ(store->GetRun("r-1")->state(), v1::INTERRUPTED);
  EXPECT_TRUE(store->ReapExpiredLeases(99999, "b").empty());  // reaped once
}

TEST_P(StoreQueueTest, ExpiredRunWithRetriesIsQueuedAgainAndCountsItsAttempts) {
  auto store = Open();
  store->PutRun(Queued("r-1", 1000, /*retries=*/1));
  const v1::RunInfo first = *store->ClaimQueuedRun(Lease("a", 5000));
  const std::vector<v1::RunInfo> requeued = store->ReapExpiredLeases(16000, "b");
  ASSERT_EQ(requeued.size(), 1u);
  EXPECT_EQ(requeued[0].state(), v1::QUEUED);
  EXPECT_THAT(requeued[0].message(), HasSubstr("queued again (attempt 2 of 2)"));
  const v1::RunInfo second = *store->ClaimQueuedRun(Lease("b", 16001));
  EXPECT_EQ(second.id(), "r-1");
  EXPECT_EQ(second.attempts(), 2);
  EXPECT_EQ(second.replica(), "b");
  // The first attempt's holder cannot renew the second attempt's lease, even as the same
  // replica name would.
  EXPECT_FALSE(store->RenewLease("r-1", LeaseHolder(first), 30000));
  EXPECT_TRUE(store->RenewLease("r-1", LeaseHolder(second), 30000));
  const std::vector<v1::RunInfo> last = store->ReapExpiredLeases(30001, "c");
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(last[0].state(), v1::INTERRUPTED);  // no attempts left
  EXPECT_EQ(last[0].attempts(), 2);
}

// A drained replica stamps the end of its attempt, then hands the run back: queued again, the
// run has not ended (a client waiting for ended_unix_ms would take it for ended).
TEST(RunLeaseTest, HandedBackRunWithRetriesIsQueuedWithoutAnEnd) {
  v1::RunInfo info;
  info.mutable_spec()->set_retries(1);
  ApplyClaim(info, {"a", "a:1", 1000, 11000});
  info.set_ended_unix_ms(2000);
  EXPECT_EQ(ApplyHandBack(info, 2000, "the replica is draining"), v1::QUEUED);
  EXPECT_EQ(info.ended_unix_ms(), 0);
  EXPECT_EQ(info.started_unix_ms(), 0);
  ApplyClaim(info, {"b", "b:1", 3000, 13000});
  EXPECT_EQ(ApplyHandBack(info, 4000, "the replica is draining"), v1::INTERRUPTED);
  EXPECT_EQ(info.ended_unix_ms(), 4000);
}

TEST_P(StoreQueueTest, HolderWritesItsEndOnlyWhileItHoldsTheLease) {
  auto store = Open();
  store->PutRun(Queued("r-1", 1000));
  v1::RunInfo run = *store->ClaimQueuedRun(Lease("a", 5000));
  run.set_state(v1::FINISHED);
  EXPECT_TRUE(store->PutRunIfHeld(run, LeaseHolder(run)));
  EXPECT_EQ(store->GetRun("r-1")->state(), v1::FINISHED);
  EXPECT_FALSE(store->RenewLease("r-1", LeaseHolder(run), 9000));  // the lease is dropped
  EXPECT_TRUE(store->ReapExpiredLeases(99999, "b").empty());       // ended runs are left
}

// FinishRun with a holder: the lease check and the result are one transaction.
TEST_P(StoreQueueTest, FinishRunStoresTheResultOnlyWhileTheHolderHoldsTheLease) {
  auto store = Open();
  store->PutRun(Queued("r-1", 1000));
  store->PutRun(Queued("r-2", 2000));
  v1::RunInfo run = *store->ClaimQueuedRun(Lease("a", 5000));
  ASSERT_EQ(run.id(), "r-1");
  const EncodedFrameChunk chunk = EncodeFrameChunks(MakeFrames(3, 2)).front();
  run.set_state(v1::FINISHED);
  EXPECT_FALSE(store->FinishRun(run, 0, chunk, "replica b"));  // not the holder
  EXPECT_EQ(store->GetRun("r-1")->state(), v1::RUNNING);
  EXPECT_TRUE(store->GetFrames("r-1").empty());
  EXPECT_TRUE(store->FinishRun(run, 0, chunk, LeaseHolder(run)));
  EXPECT_EQ(store->GetRun("r-1")->state(), v1::FINISHED);
  EXPECT_EQ(store->GetFrames("r-1").size(), 3u);

  // Reaped before it ended: the old holder stores nothing.
  v1::RunInfo second = *store->ClaimQueuedRun(Lease("a", 6000));
  ASSERT_EQ(store->ReapExpiredLeases(99999, "b").size(), 1u);
  second.set_state(v1::FINISHED);
  EXPECT_FALSE(store->FinishRun(second, 0, chunk, LeaseHolder(second)));
  EXPECT_EQ(store->GetRun("r-2")->state(), v1::INTERRUPTED);
  EXPECT_TRUE(store->GetFrames("r-2").empty());
}

TEST_P(StoreQueueTest, EndQueuedRunOnlyEndsARunStillQueued) {
  auto store = Open();
  store->PutRun(Queued("r-1", 1000));
  store->PutRun(Queued("r-2", 2000));
  ASSERT_EQ(store->ClaimQueuedRun(Lease("a", 5000))->id(), "r-1");
  EXPECT_FALSE(store->EndQueuedRun("r-1", v1::CANCELLED, "cancelled", 6000).has_value());
  EXPECT_FALSE(store->EndQueuedRun("r-missing", v1::CANCELLED, "cancelled", 6000).has_value());
  const auto ended = store->EndQueuedRun("r-2", v1::CANCELLED, "cancelled before it started", 6000);
  ASSERT_TRUE(ended.has_value());
  EXPECT_EQ(ended->state(), v1::CANCELLED);
  EXPECT_EQ(ended->ended_unix_ms(), 6000);
  EXPECT_TRUE(testing::Same(*store->GetRun("r-2"), *ended));
  EXPECT_FALSE(store->ClaimQueuedRun(Lease("a", 7000)).has_value());
}

// A RUNNING row written without a lease (by a server of schema version 2, or one that died
// before the queue existed) counts as expired.
TEST_P(StoreQueueTest, RunningRunWithoutALeaseIsReaped) {
  auto store = Open();
  store->PutRun(MakeRun("r-old", v1::RUNNING, 1000));
  const std::vector<v1::RunInfo> reaped = store->ReapExpiredLeases(2000, "b");
  ASSERT_EQ(reaped.size(), 1u);
  EXPECT_EQ(reaped[0].state(), v1::INTERRUPTED);
}

}  // namespace
}  // namespace mbstream
