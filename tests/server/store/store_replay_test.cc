// Store: the chunk that holds a frame (replay seeks), the replays' probe sets, and the
// migration of a version-1 store that has none.
#include <gmock/gmock.h>

#include "server/store/frame_chunks.h"
#include "server/store/sqlite_connection.h"
#include "server/store/store.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream::testing {
namespace {

v1::ProbeSet MakeSet(const std::string& id, const std::string& run_id) {
  v1::ProbeSet set;
  set.set_id(id);
  set.set_run_id(run_id);
  set.set_viewer("host:42");
  set.set_scene("IRB 1600");
  return set;
}

class StoreReplayTest : public testing::StoreBackendTest {};
INSTANTIATE_STORE_BACKENDS(StoreReplayTest);

TEST_P(StoreReplayTest, FrameChunkHoldingFindsTheChunkOfAnyFrame) {
  auto store = Open();
  store->PutRun(MakeRun("r-1", v1::FINISHED, 1));
  store->FinishRun(MakeRun("r-1", v1::FINISHED, 1), MakeFrames(2 * kFramesPerChunk + 10, 2));
  EXPECT_EQ(store->FrameChunkHolding("r-1", 0), 0);
  EXPECT_EQ(store->FrameChunkHolding("r-1", kFramesPerChunk - 1), 0);
  EXPECT_EQ(store->FrameChunkHolding("r-1", kFramesPerChunk), 1);
  EXPECT_EQ(store->FrameChunkHolding("r-1", 2 * kFramesPerChunk + 9), 2);
  EXPECT_FALSE(store->FrameChunkHolding("r-1", 2 * kFramesPerChunk + 10));
  EXPECT_FALSE(store->FrameChunkHolding("r-2", 0));
}

TEST_P(StoreReplayTest, ProbeSetsAreKeptPerRunWithTheirReports) {
  auto store = Open();
  store->CreateProbeSet(MakeSet("ps-a", "r-1"));
  store->CreateProbeSet(MakeSet("ps-b", "r-1"));
  store->CreateProbeSet(MakeSet("ps-c", "r-2"));
  store->AddProbeSetReports("ps-a", {MakeProbe("r-1", 2, "tcp"), MakeProbe("r-1", 1, "tcp")});
  store->AddProbeSetReports("ps-a", {MakeProbe("r-1", 1, "tcp")});  // replaces: a replay looped
  store->AddProbeSetReports("ps-b", {MakeProbe("r-1", 7, "tcp")});
  store->AddProbes({MakeProbe("r-1", 0, "tcp")});  // the live run's: no set

  const std::vector<v1::ProbeSet> sets = store->ListProbeSets("r-1");
  ASSERT_EQ(sets.size(), 2u);
  EXPECT_EQ(sets[0].id(), "ps-a");
  EXPECT_EQ(sets[0].reports(), 2);
  EXPECT_EQ(sets[0].viewer(), "host:42");
  EXPECT_EQ(sets[0].scene(), "IRB 1600");
  EXPECT_GT(sets[0].created_unix_ms(), 0);
  EXPECT_EQ(sets[1].id(), "ps-b");
  EXPECT_EQ(sets[1].reports(), 1);
  const std::vector<v1::ProbeReport> reports = store->GetProbeSetReports("ps-a");
  ASSERT_EQ(reports.size(), 2u);
  EXPECT_EQ(reports[0].seq(), 1);
  EXPECT_EQ(reports[1].seq(), 2);
  EXPECT_EQ(store->GetProbes("r-1").size(), 1u);
  EXPECT_EQ(store->GetProbeSet("ps-c")->run_id(), "r-2");
  EXPECT_FALSE(store->GetProbeSet("ps-none"));
  EXPECT_TRUE(store->GetProbeSetReports("ps-none").empty());
}

TEST(StoreReplaySqliteTest, VersionOneStoreGainsProbeSetsAndKeepsItsRuns) {
  TempDirectory temp;
  {
    auto store = Store::Open(temp.str());
    store->PutRun(MakeRun("r-1", v1::FINISHED, 1));
  }
  {  // what a version-1 server left: no probe set tables, no leases (version 3)
    auto raw = SqliteConnection::Open((temp.path() / Store::kFileName).string());
    raw.Exec(
        "DROP TABLE probe_set_reports; DROP TABLE probe_sets; DROP INDEX runs_queue; "
        "ALTER TABLE runs DROP COLUMN lease_holder; "
        "ALTER TABLE runs DROP COLUMN lease_expires_unix_ms; " +
            std::string(kDropFrameFileColumns) + "PRAGMA user_version = 1",
        "make a version-1 store");
  }
  auto store = Store::Open(temp.str());
  EXPECT_TRUE(store->GetRun("r-1"));
  store->CreateProbeSet(MakeSet("ps-a", "r-1"));
  EXPECT_EQ(store->ListProbeSets("r-1").size(), 1u);
}

}  // namespace
}  // namespace mbstream::testing
