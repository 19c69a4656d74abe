// Store: a sweep's runs found by the index of sweep ids, the mark of a cancelled sweep (one
// statement on the rows that exist: a deleted run is not written again, and the runs' writers
// never undo the mark), on both backends; a version-6 store opened by this build finds the
// sweeps of the runs it holds.
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/store/sqlite_connection.h"
#include "server/store/sqlite_statement.h"
#include "server/store/store.h"
#include "server/store/sweep_sql.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;
using testing::MakeRun;
using testing::TempDirectory;

v1::RunInfo SweepRun(const std::string& id, const std::string& sweep_id, int point,
                     int64_t created_unix_ms) {
  v1::RunInfo info = MakeRun(id, v1::QUEUED, created_unix_ms);
  info.set_sweep_id(sweep_id);
  info.set_sweep_point(point);
  info.set_sweep_points(3);
  return info;
}

std::vector<std::string> IdsOf(const std::vector<v1::RunInfo>& runs) {
  std::vector<std::string> ids;
  for (const v1::RunInfo& run : runs) ids.push_back(run.id());
  return ids;
}

class StoreSweepsTest : public testing::StoreBackendTest {
 protected:
  // Sweep s-a (r-1, r-2 and, added alone, r-4), sweep s-b (r-3) and r-5 started alone.
  void AddRuns(Store& store) {
    ASSERT_TRUE(store.AddRuns({SweepRun("r-1", "s-a", 0, 1000), SweepRun("r-2", "s-a", 1, 1000),
                               SweepRun("r-3", "s-b", 0, 1001)}));
    store.PutRun(SweepRun("r-4", "s-a", 2, 1002));
    store.PutRun(MakeRun("r-5", v1::QUEUED, 1003));
  }
};
INSTANTIATE_STORE_BACKENDS(StoreSweepsTest);

TEST_P(StoreSweepsTest, ListSweepRunsFindsTheSweepsRunsOnlyOldestFirst) {
  auto store = Open();
  AddRuns(*store);
  EXPECT_EQ(IdsOf(store->ListSweepRuns("s-a")), (std::vector<std::string>{"r-1", "r-2", "r-4"}));
  EXPECT_EQ(IdsOf(store->ListSweepRuns("s-b")), (std::vector<std::string>{"r-3"}));
  EXPECT_TRUE(store->ListSweepRuns("s-unknown").empty());
  EXPECT_TRUE(store->ListSweepRuns("").empty());  // a run started alone is in no sweep

  ASSERT_TRUE(store->SetRunKeep("r-2", true));
  const std::vector<v1::RunInfo> runs = store->ListSweepRuns("s-a");
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_TRUE(runs[1].keep());  // as GetRun shows it
  EXPECT_EQ(runs[1].sweep_point(), 1);
  EXPECT_FALSE(runs[0].sweep_cancelled());

  store.reset();  // and after a restart
  store = Open();
  EXPECT_EQ(IdsOf(store->ListSweepRuns("s-a")), (std::vector<std::string>{"r-1", "r-2", "r-4"}));
}

TEST_P(StoreSweepsTest, MarkSweepCancelledMarksEveryRunOfTheSweepAndWritersKeepTheMark) {
  auto store = Open();
  AddRuns(*store);
  EXPECT_FALSE(store->SweepCancelled("s-a"));
  EXPECT_EQ(store->MarkSweepCancelled("s-a"), 3);
  EXPECT_TRUE(store->SweepCancelled("s-a"));
  EXPECT_FALSE(store->SweepCancelled("s-b"));
  EXPECT_FALSE(store->SweepCancelled("s-unknown"));
  EXPECT_EQ(store->MarkSweepCancelled("s-a"), 0);  // marked already
  EXPECT_EQ(store->MarkSweepCancelled("s-unknown"), 0);
  for (const v1::RunInfo& run : store->ListSweepRuns("s-a")) EXPECT_TRUE(run.sweep_cancelled());
  EXPECT_TRUE(store->GetRun("r-1")->sweep_cancelled());
  EXPECT_FALSE(store->GetRun("r-3")->sweep_cancelled());  // another sweep's
  EXPECT_FALSE(store->GetRun("r-5")->sweep_cancelled());

  // A run's own writer, with the info it had before the mark, leaves the mark.
  v1::RunInfo ended = SweepRun("r-1", "s-a", 0, 1000);
  ended.set_state(v1::CANCELLED);
  store->PutRun(ended);
  const std::optional<v1::RunInfo> stored = store->GetRun("r-1");
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(stored->state(), v1::CANCELLED);
  EXPECT_TRUE(stored->sweep_cancelled());
  bool in_list = false;
  for (const v1::RunInfo& run : store->ListRuns()) {
    if (run.id() == "r-1") in_list = run.sweep_cancelled();
  }
  EXPECT_TRUE(in_list);
}

// The fault the one statement removes: a run deleted (DeleteRuns, retention) between a read
// and a write of the mark came back as a row of its own.
TEST_P(StoreSweepsTest, ADeletedRunIsNotCreatedAgainByTheMark) {
  auto store = Open();
  AddRuns(*store);
  ASSERT_TRUE(store->DeleteRun("r-2"));
  EXPECT_EQ(store->MarkSweepCancelled("s-a"), 2);
  EXPECT_FALSE(store->GetRun("r-2").has_value());
  EXPECT_EQ(IdsOf(store->ListSweepRuns("s-a")), (std::vector<std::string>{"r-1", "r-4"}));
  EXPECT_EQ(store->ListRuns().size(), 4u);
}

// SQLite's plan of `sql` (EXPLAIN QUERY PLAN's details, a line each).
std::string PlanOf(SqliteConnection& raw, const std::string& sql) {
  SqliteStatement plan(raw, "EXPLAIN QUERY PLAN " + sql, "explain");
  std::string details;
  while (plan.Step()) details += std::string(plan.ColumnText(3)) + "\n";
  plan.Reset();
  return details;
}

TEST(StoreSweepsSqliteTest, ASweepsRunsAndItsMarkAreFoundByTheIndex) {
  TempDirectory temp;
  Store::Open(temp.str());
  auto raw = SqliteConnection::Open((temp.path() / Store::kFileName).string());
  EXPECT_THAT(PlanOf(raw, kSelectSweepRunsSql), HasSubstr("USING INDEX runs_by_sweep"));
  // The mark from the index alone: no row (and its RunInfo) read.
  EXPECT_THAT(PlanOf(raw, kSweepCancelledSql), HasSubstr("USING COVERING INDEX runs_by_sweep"));
}

TEST(StoreSweepsSqliteTest, AVersionSixStoreFindsItsSweepsAfterTheUpgrade) {
  TempDirectory temp;
  {
    auto store = Store::Open(temp.str());
    v1::RunInfo cancelled = SweepRun("r-1", "s-a", 0, 1000);
    cancelled.set_state(v1::CANCELLED);
    cancelled.set_sweep_cancelled(true);  // where version 6 kept the mark: in the info
    store->PutRun(cancelled);
    store->PutRun(SweepRun("r-2", "s-a", 1, 1001));
    store->PutRun(MakeRun("r-3", v1::FINISHED, 1002));
  }
  {  // what a version-6 server left
    auto raw = SqliteConnection::Open((temp.path() / Store::kFileName).string());
    raw.Exec(std::string(kDropSweepColumns) + "PRAGMA user_version = 6", "make a version-6 store");
  }
  auto store = Store::Open(temp.str());
  const std::vector<v1::RunInfo> runs = store->ListSweepRuns("s-a");
  EXPECT_EQ(IdsOf(runs), (std::vector<std::string>{"r-1", "r-2"}));
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_TRUE(runs[0].sweep_cancelled());
  EXPECT_FALSE(runs[1].sweep_cancelled());
  EXPECT_EQ(store->MarkSweepCancelled("s-a"), 1);  // r-2; r-1's mark was carried over
  EXPECT_TRUE(store->GetRun("r-2")->sweep_cancelled());
}

}  // namespace
}  // namespace mbstream
