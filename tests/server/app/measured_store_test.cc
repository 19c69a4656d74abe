// MeasuredStore: the runs, frames, probes and store operations that pass through it move the
// server's metrics, and it stores what the store beneath it stores.
#include <gmock/gmock.h>

#include "server/app/measured_store.h"
#include "server/app/server_metrics.h"
#include "server/metrics/metric_registry.h"
#include "server/store/frame_chunks.h"
#include "server/store/run_lease.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream::testing {
namespace {

using ::testing::HasSubstr;

class MeasuredStoreTest : public ::testing::Test {
 protected:
  metrics::Registry registry_;
  ServerMetrics metrics_{registry_};
  TempDirectory temp_;
  MeasuredStore store_{Store::Open(temp_.str()), metrics_};
};

TEST_F(MeasuredStoreTest, CountsRunsByStateOncePerRun) {
  store_.PutRun(MakeRun("r-1", v1::QUEUED, 1000));
  store_.PutRun(MakeRun("r-2", v1::QUEUED, 1001));
  EXPECT_EQ(metrics_.runs(v1::QUEUED).value(), 2);
  store_.PutRun(MakeRun("r-1", v1::RUNNING, 1000));
  EXPECT_EQ(metrics_.runs(v1::QUEUED).value(), 1);
  EXPECT_EQ(metrics_.runs(v1::RUNNING).value(), 1);
  store_.FinishRun(MakeRun("r-1", v1::FINISHED, 1000), MakeFrames(10, 2));
  store_.PutRun(MakeRun("r-1", v1::FINISHED, 1000));  // the final row again: counted once
  store_.PutRun(MakeRun("r-2", v1::CANCELLED, 1001));
  store_.PutRun(MakeRun("r-9", v1::FAILED, 1002));  // never queued here: another replica's
  EXPECT_EQ(metrics_.runs(v1::QUEUED).value(), 0);
  EXPECT_EQ(metrics_.runs(v1::RUNNING).value(), 0);
  EXPECT_EQ(metrics_.runs_ended(v1::FINISHED).value(), 1);
  EXPECT_EQ(metrics_.runs_ended(v1::CANCELLED).value(), 1);
  EXPECT_EQ(metrics_.runs_ended(v1::FAILED).value(), 0);
  EXPECT_EQ(metrics_.frames().value(), 10);
  EXPECT_EQ(store_.GetFrames("r-1").size(), 10u);  // stored beneath
  EXPECT_EQ(metrics_.store(StoreOperation::kPutRun).count(), 6u);
  EXPECT_EQ(metrics_.store(StoreOperation::kFinishRun).count(), 1u);
}

TEST_F(MeasuredStoreTest, CountsEveryRunOfABatchAndTimesTheBatchOnce) {
  EXPECT_TRUE(store_.AddRuns({MakeRun("r-1", v1::QUEUED, 1000), MakeRun("r-2", v1::QUEUED, 1000),
                              MakeRun("r-3", v1::QUEUED, 1000)}));
  EXPECT_EQ(metrics_.runs(v1::QUEUED).value(), 3);
  EXPECT_EQ(metrics_.store(StoreOperation::kPutRun).count(), 1u);
  EXPECT_EQ(store_.ListRuns().size(), 3u);
  // A batch with a taken id stores nothing and counts nothing.
  EXPECT_FALSE(
      store_.AddRuns({MakeRun("r-4", v1::QUEUED, 1000), MakeRun("r-2", v1::QUEUED, 1000)}));
  EXPECT_EQ(metrics_.runs(v1::QUEUED).value(), 3);
  EXPECT_EQ(store_.ListRuns().size(), 3u);
}

// A private store's claim (RunQueue::ClaimPrivate) writes nothing and is counted; a result
// the store refused (the lease is not held) is not.
TEST_F(MeasuredStoreTest, CountsAClaimMadeWithoutTheStoreAndOnlyStoredResults) {
  store_.PutRun(MakeRun("r-1", v1::QUEUED, 1000));
  store_.NoteClaimed(MakeRun("r-1", v1::RUNNING, 1000));
  EXPECT_EQ(metrics_.runs(v1::QUEUED).value(), 0);
  EXPECT_EQ(metrics_.runs(v1::RUNNING).value(), 1);
  EXPECT_EQ(store_.GetRun("r-1")->state(), v1::QUEUED);  // nothing written
  const EncodedFrameChunk chunk = EncodeFrameChunks(MakeFrames(4, 2)).front();
  EXPECT_FALSE(store_.FinishRun(MakeRun("r-1", v1::FINISHED, 1000), 0, chunk, "replica x"));
  EXPECT_EQ(metrics_.runs(v1::RUNNING).value(), 1);
  EXPECT_EQ(metrics_.frames().value(), 0);
  EXPECT_TRUE(store_.FinishRun(MakeRun("r-1", v1::FINISHED, 1000), 0, chunk, ""));
  EXPECT_EQ(metrics_.runs(v1::RUNNING).value(), 0);
  EXPECT_EQ(metrics_.runs_ended(v1::FINISHED).value(), 1);
  EXPECT_EQ(metrics_.frames().value(), 4);
}

TEST_F(MeasuredStoreTest, RunQueuedHereAndClaimedByAnotherReplicaLeavesTheQueuedGauge) {
  store_.PutRun(MakeRun("r-1", v1::QUEUED, 1000));
  store_.PutRun(MakeRun("r-2", v1::QUEUED, 1001));
  ASSERT_EQ(metrics_.runs(v1::QUEUED).value(), 2);
  {  // another replica, on the same store, claims the oldest queued run (r-1)
    std::unique_ptr<Store> other = Store::Open(temp_.str());
    RunLease lease;
    lease.replica = "other";
    lease.now_unix_ms = 2000;
    lease.expires_unix_ms = 9000;
    ASSERT_EQ(other->ClaimQueuedRun(lease)->id(), "r-1");
  }
  store_.GetRun("r-2");  // still queued: counted here
  EXPECT_EQ(metrics_.runs(v1::QUEUED).value(), 2);
  EXPECT_EQ(store_.GetRun("r-1")->state(), v1::RUNNING);  // this replica looks at its run
  EXPECT_EQ(metrics_.runs(v1::QUEUED).value(), 1);
  EXPECT_EQ(metrics_.runs(v1::RUNNING).value(), 0);  // the other replica's to count
  store_.GetRun("r-1");
  EXPECT_EQ(metrics_.runs(v1::QUEUED).value(), 1);
  // This replica's own claim of r-2 moves it from queued to running, as before.
  RunLease here;
  here.replica = "here";
  here.now_unix_ms = 3000;
  here.expires_unix_ms = 9000;
  ASSERT_EQ(store_.ClaimQueuedRun(here)->id(), "r-2");
  store_.GetRun("r-2");
  EXPECT_EQ(metrics_.runs(v1::QUEUED).value(), 0);
  EXPECT_EQ(metrics_.runs(v1::RUNNING).value(), 1);
}

TEST_F(MeasuredStoreTest, ObservesProbeLatencyAndExposesEverything) {
  store_.PutRun(MakeRun("r-1", v1::RUNNING, 1000));
  std::vector<v1::ProbeReport> reports(3);
  for (int i = 0; i < 3; ++i) {
    reports[i].set_run_id("r-1");
    reports[i].set_seq(i);
    reports[i].set_probe("Tcp");
    reports[i].set_latency_us(250 * (i + 1));  // 250, 500, 750 us
  }
  store_.AddProbes(reports);
  EXPECT_EQ(metrics_.probe_latency().count(), 3u);
  EXPECT_DOUBLE_EQ(metrics_.probe_latency().sum(), 1.5e-3);
  metrics_.SetSubscriberCount([] { return 2.0; });
  const std::string text = registry_.Exposition();
  EXPECT_THAT(text, HasSubstr("mbstream_runs{state=\"running\"} 1\n"));
  EXPECT_THAT(text, HasSubstr("mbstream_runs_ended_total{state=\"interrupted\"} 0\n"));
  EXPECT_THAT(text, HasSubstr("mbstream_probe_latency_seconds_bucket{le=\"0.0008\"} 3\n"));
  EXPECT_THAT(text, HasSubstr("mbstream_probe_latency_seconds_count 3\n"));
  EXPECT_THAT(
      text,
      HasSubstr("mbstream_store_operation_duration_seconds_count{operation=\"add_probes\"} 1"));
  EXPECT_THAT(text, HasSubstr("mbstream_subscribers 2\n"));
  EXPECT_THAT(text, HasSubstr("mbstream_build_info{version=\""));
  EXPECT_THAT(text, HasSubstr("# TYPE process_start_time_seconds gauge\n"));
}

TEST_F(MeasuredStoreTest, CountsRunsMarkedInterruptedAtStart) {
  {
    std::unique_ptr<Store> plain = Store::Open(temp_.str() + "-b");
    plain->PutRun(MakeRun("r-1", v1::RUNNING, 1000));
  }
  MeasuredStore reopened(Store::Open(temp_.str() + "-b"), metrics_);
  EXPECT_EQ(reopened.MarkUnfinishedRunsInterrupted("restart"), 1);
  EXPECT_EQ(metrics_.runs_ended(v1::INTERRUPTED).value(), 1);
  std::filesystem::remove_all(temp_.str() + "-b");
}

}  // namespace
}  // namespace mbstream::testing
