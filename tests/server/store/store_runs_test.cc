// Store: run rows round trip, are replaced in place, list oldest first, and unfinished ones
// become INTERRUPTED at start.
#include <chrono>

#include <gtest/gtest.h>

#include "server/store/store.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream {
namespace {

using testing::MakeFrames;
using testing::MakeRun;
using testing::Same;
using testing::TempDirectory;

class StoreRunsTest : public testing::StoreBackendTest {};
INSTANTIATE_STORE_BACKENDS(StoreRunsTest);

TEST_P(StoreRunsTest, PutGetRoundTrip) {
  auto store = Open();
  const v1::RunInfo run = MakeRun("r-1", v1::QUEUED, 1000);
  store->PutRun(run);
  const auto loaded = store->GetRun("r-1");
  ASSERT_TRUE(loaded.has_value());
  EXPECT_TRUE(Same(*loaded, run));
  EXPECT_FALSE(store->GetRun("r-missing").has_value());
}

TEST_P(StoreRunsTest, PutRunReplacesKeepingOrderAndFrames) {
  auto store = Open();
  store->PutRun(MakeRun("r-1", v1::QUEUED, 1000));
  store->PutRun(MakeRun("r-2", v1::QUEUED, 1000));  // same millisecond: insertion order
  store->FinishRun(MakeRun("r-1", v1::FINISHED, 1000), MakeFrames(10, 2));
  v1::RunInfo updated = MakeRun("r-1", v1::FINISHED, 1000);
  updated.set_probe_reports(7);
  store->PutRun(updated);  // must not drop the frames (no delete + insert)
  const auto runs = store->ListRuns();
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].id(), "r-1");
  EXPECT_EQ(runs[1].id(), "r-2");
  EXPECT_TRUE(Same(runs[0], updated));
  EXPECT_EQ(store->GetFrames("r-1").size(), 10u);
}

TEST_P(StoreRunsTest, AddRunsWritesEveryRowInOrderOrNoneWhenAnIdIsTaken) {
  auto store = Open();
  const v1::RunInfo stored = MakeRun("r-2", v1::FINISHED, 1000);
  store->PutRun(stored);
  v1::RunInfo again = MakeRun("r-2", v1::QUEUED, 1000);  // a new run given a taken id
  again.set_expected_frames(41);
  EXPECT_FALSE(store->AddRuns({MakeRun("r-1", v1::QUEUED, 1000), again}));
  ASSERT_EQ(store->ListRuns().size(), 1u);           // not even r-1, stored before the taken id
  EXPECT_TRUE(Same(*store->GetRun("r-2"), stored));  // untouched

  EXPECT_TRUE(store->AddRuns({MakeRun("r-1", v1::QUEUED, 1000), MakeRun("r-3", v1::QUEUED, 1000)}));
  const auto runs = store->ListRuns();
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(runs[0].id(), "r-2");
  EXPECT_EQ(runs[1].id(), "r-1");
  EXPECT_EQ(runs[2].id(), "r-3");
  EXPECT_TRUE(Same(runs[2], MakeRun("r-3", v1::QUEUED, 1000)));
  EXPECT_FALSE(store->AddRuns({MakeRun("r-3", v1::QUEUED, 2000)}));  // a batch of one
  EXPECT_EQ(store->GetRun("r-3")->created_unix_ms(), 1000);
}

TEST_P(StoreRunsTest, ListsOldestFirst) {
  auto store = Open();
  store->PutRun(MakeRun("r-c", v1::FINISHED, 3000));
  store->PutRun(MakeRun("r-a", v1::FINISHED, 1000));
  store->PutRun(MakeRun("r-b", v1::FINISHED, 2000));
  const auto runs = store->ListRuns();
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(runs[0].id(), "r-a");
  EXPECT_EQ(runs[1].id(), "r-b");
  EXPECT_EQ(runs[2].id(), "r-c");
}

TEST_P(StoreRunsTest, MarkUnfinishedRunsInterrupted) {
  {
    auto store = Open();
    store->PutRun(MakeRun("r-queued", v1::QUEUED, 1000));
    store->PutRun(MakeRun("r-running", v1::RUNNING, 2000));
    store->PutRun(MakeRun("r-finished", v1::FINISHED, 3000));
    store->PutRun(MakeRun("r-cancelled", v1::CANCELLED, 4000));
  }  // the "crash"
  auto store = Open();
  const int64_t before_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                                std::chrono::system_clock::now().time_since_epoch())
                                .count();
  EXPECT_EQ(store->MarkUnfinishedRunsInterrupted("server restarted"), 2);
  for (const char* id : {"r-queued", "r-running"}) {
    const auto run = store->GetRun(id);
    ASSERT_TRUE(run.has_value());
    EXPECT_EQ(run->state(), v1::INTERRUPTED) << id;
    EXPECT_EQ(run->message(), "server restarted");
    EXPECT_GE(run->ended_unix_ms(), before_ms);
    EXPECT_EQ(run->spec().method(), "bdf");  // the rest of the info is kept
  }
  EXPECT_EQ(store->GetRun("r-finished")->state(), v1::FINISHED);
  EXPECT_EQ(store->GetRun("r-cancelled")->state(), v1::CANCELLED);
  EXPECT_EQ(store->MarkUnfinishedRunsInterrupted("again"), 0);
}

}  // namespace
}  // namespace mbstream
