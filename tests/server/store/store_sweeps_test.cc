// Store: a sweep's runs found by the index of sweep ids, the mark of a cancelled sweep (one
// statement on the rows that exist: a deleted run is not written again, and the runs' writers
// never undo the mark), on both backends; a version-6 store opened by this build finds the
// sweeps of the runs it holds. The sweeps the server feeds (version 8): stored whole, their
// points queued only from their next point and within their window, counted and paged by
// point, and their unfinished runs left to the next server.
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

StoredSweep MakeSweep(const std::string& id, int total, int window) {
  StoredSweep sweep;
  sweep.id = id;
  sweep.model_id = "m-abc";
  sweep.owner = "alice";
  sweep.created_unix_ms = 1000;
  sweep.total_points = total;
  sweep.window = window;
  sweep.definition = std::string(
      "\x0a\x00"
      "definition",
      12);  // bytes, NUL included
  return sweep;
}

// Runs of points first.. of sweep `sweep_id`, QUEUED (ids r-<sweep>-<point>).
std::vector<v1::RunInfo> Points(const std::string& sweep_id, int first, int count) {
  std::vector<v1::RunInfo> runs;
  for (int k = first; k < first + count; ++k) {
    runs.push_back(SweepRun("r-" + sweep_id + "-" + std::to_string(k), sweep_id, k, 2000 + k));
  }
  return runs;
}

TEST_P(StoreSweepsTest, AStoredSweepIsReadBackWholeAndListedWhileItHasPointsLeft) {
  auto store = Open();
  ASSERT_TRUE(store->AddSweep(MakeSweep("s-f", 5, 2)));
  EXPECT_FALSE(store->AddSweep(MakeSweep("s-f", 9, 9)));  // the id is taken
  std::optional<StoredSweep> read = store->GetSweep("s-f", true);
  ASSERT_TRUE(read);
  EXPECT_EQ(read->model_id, "m-abc");
  EXPECT_EQ(read->owner, "alice");
  EXPECT_EQ(read->created_unix_ms, 1000);
  EXPECT_EQ(read->total_points, 5);
  EXPECT_EQ(read->next_point, 0);
  EXPECT_EQ(read->window, 2);
  EXPECT_FALSE(read->cancelled);
  EXPECT_EQ(read->definition, MakeSweep("s-f", 5, 2).definition);
  EXPECT_TRUE(store->GetSweep("s-f", false)->definition.empty());
  EXPECT_FALSE(store->GetSweep("s-nosuch", true));

  std::vector<StoredSweep> open = store->ListOpenSweeps();
  ASSERT_EQ(open.size(), 1u);
  EXPECT_EQ(open[0].id, "s-f");
  EXPECT_TRUE(open[0].definition.empty());

  ASSERT_EQ(store->AddSweepRuns("s-f", Points("s-f", 0, 2)), SweepFeed::kAdded);
  open = store->ListOpenSweeps();
  ASSERT_EQ(open.size(), 1u);
  EXPECT_EQ(open[0].next_point, 2);
  EXPECT_EQ(open[0].unfinished_runs, 2);

  store.reset();  // and after a restart
  store = Open();
  EXPECT_EQ(store->GetSweep("s-f", false)->next_point, 2);
  EXPECT_EQ(store->GetSweep("s-f", false)->unfinished_runs, 2);
}

TEST_P(StoreSweepsTest, PointsAreQueuedOnlyFromTheNextPointAndWithinTheWindow) {
  auto store = Open();
  ASSERT_TRUE(store->AddSweep(MakeSweep("s-f", 5, 2)));
  EXPECT_EQ(store->AddSweepRuns("s-f", Points("s-f", 1, 1)), SweepFeed::kRefused);  // not next
  EXPECT_EQ(store->AddSweepRuns("s-f", Points("s-f", 0, 3)), SweepFeed::kRefused);  // window 2
  EXPECT_EQ(store->AddSweepRuns("s-nosuch", Points("s-nosuch", 0, 1)), SweepFeed::kRefused);
  EXPECT_TRUE(store->ListSweepRuns("s-f").empty());  // nothing of the refused calls

  ASSERT_EQ(store->AddSweepRuns("s-f", Points("s-f", 0, 2)), SweepFeed::kAdded);
  // Another replica that read the sweep before: its points are taken, its window is full.
  EXPECT_EQ(store->AddSweepRuns("s-f", Points("s-f", 0, 1)), SweepFeed::kRefused);
  EXPECT_EQ(store->AddSweepRuns("s-f", Points("s-f", 2, 1)), SweepFeed::kRefused);

  v1::RunInfo ended = *store->GetRun("r-s-f-0");
  ended.set_state(v1::FINISHED);
  store->PutRun(ended);  // a place frees up
  // A taken id leaves everything as it was.
  std::vector<v1::RunInfo> taken = Points("s-f", 2, 1);
  taken[0].set_id("r-s-f-1");
  EXPECT_EQ(store->AddSweepRuns("s-f", taken), SweepFeed::kIdTaken);
  EXPECT_EQ(store->GetSweep("s-f", false)->next_point, 2);
  ASSERT_EQ(store->AddSweepRuns("s-f", Points("s-f", 2, 1)), SweepFeed::kAdded);

  // A point the model refused is stored FAILED and takes no place in the window.
  std::vector<v1::RunInfo> refused = Points("s-f", 3, 1);
  refused[0].set_state(v1::FAILED);
  ASSERT_EQ(store->AddSweepRuns("s-f", refused), SweepFeed::kAdded);
  EXPECT_EQ(store->GetSweep("s-f", false)->next_point, 4);

  Store::StateCounts counts = store->CountSweepRuns("s-f");
  EXPECT_EQ(counts[v1::QUEUED], 2);
  EXPECT_EQ(counts[v1::FINISHED], 1);
  EXPECT_EQ(counts[v1::FAILED], 1);

  // Cancelled: no more points.
  EXPECT_EQ(store->MarkSweepCancelled("s-f"), 4);
  EXPECT_TRUE(store->GetSweep("s-f", false)->cancelled);
  EXPECT_TRUE(store->SweepCancelled("s-f"));
  EXPECT_TRUE(store->ListOpenSweeps().empty());
  ended = *store->GetRun("r-s-f-1");
  ended.set_state(v1::CANCELLED);
  store->PutRun(ended);
  EXPECT_EQ(store->AddSweepRuns("s-f", Points("s-f", 4, 1)), SweepFeed::kRefused);
}

TEST_P(StoreSweepsTest, ASweepsRunsArePagedByPoint) {
  auto store = Open();
  ASSERT_TRUE(store->AddSweep(MakeSweep("s-p", 6, 6)));
  // Stored out of point order (a point queued again keeps its row).
  std::vector<v1::RunInfo> runs = Points("s-p", 0, 6);
  std::swap(runs[1], runs[4]);
  for (const v1::RunInfo& run : runs) store->PutRun(run);
  EXPECT_EQ(IdsOf(store->ListSweepRuns("s-p", 2, 3)),
            (std::vector<std::string>{"r-s-p-2", "r-s-p-3", "r-s-p-4"}));
  EXPECT_EQ(IdsOf(store->ListSweepRuns("s-p", 5)), (std::vector<std::string>{"r-s-p-5"}));
  EXPECT_TRUE(store->ListSweepRuns("s-p", 6).empty());
  v1::RunInfo ended = *store->GetRun("r-s-p-3");
  ended.set_state(v1::FINISHED);
  store->PutRun(ended);
  EXPECT_EQ(IdsOf(store->ListSweepRuns("s-p", 2, 0, true)),
            (std::vector<std::string>{"r-s-p-2", "r-s-p-4", "r-s-p-5"}));
}

TEST_P(StoreSweepsTest, UnfinishedRunsOfAFedSweepAreLeftToTheNextServer) {
  auto store = Open();
  ASSERT_TRUE(store->AddSweep(MakeSweep("s-f", 4, 4)));
  ASSERT_EQ(store->AddSweepRuns("s-f", Points("s-f", 0, 2)), SweepFeed::kAdded);
  ASSERT_TRUE(store->AddSweep(MakeSweep("s-c", 4, 4)));
  ASSERT_EQ(store->AddSweepRuns("s-c", Points("s-c", 0, 1)), SweepFeed::kAdded);
  store->MarkSweepCancelled("s-c");
  AddRuns(*store);  // s-a: runs of a sweep started in slices (no row), and a run alone

  EXPECT_EQ(IdsOf(store->ListUnfinishedSweepRuns()),
            (std::vector<std::string>{"r-s-f-0", "r-s-f-1"}));
  // Those of the cancelled sweep, of the sweeps without a row and alone: INTERRUPTED.
  EXPECT_EQ(store->MarkUnfinishedRunsInterrupted("the server stopped"), 6);
  EXPECT_EQ(store->GetRun("r-s-f-0")->state(), v1::QUEUED);
  EXPECT_EQ(store->GetRun("r-s-c-0")->state(), v1::INTERRUPTED);
  EXPECT_EQ(store->GetRun("r-1")->state(), v1::INTERRUPTED);
  EXPECT_EQ(store->GetRun("r-5")->state(), v1::INTERRUPTED);
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

TEST(StoreSweepsSqliteTest, AVersionSevenStoreKeepsItsSweepsPointsAfterTheUpgrade) {
  TempDirectory temp;
  {
    auto store = Store::Open(temp.str());
    store->PutRun(SweepRun("r-2", "s-a", 1, 1000));  // stored before point 0
    store->PutRun(SweepRun("r-1", "s-a", 0, 1001));
  }
  {  // what a version-7 server left
    auto raw = SqliteConnection::Open((temp.path() / Store::kFileName).string());
    raw.Exec(std::string(kDropSweepsTable) + "PRAGMA user_version = 7", "make a version-7 store");
  }
  auto store = Store::Open(temp.str());
  EXPECT_EQ(IdsOf(store->ListSweepRuns("s-a")), (std::vector<std::string>{"r-1", "r-2"}));
  EXPECT_EQ(IdsOf(store->ListSweepRuns("s-a", 1)), (std::vector<std::string>{"r-2"}));
  EXPECT_FALSE(store->GetSweep("s-a", false));  // started in slices: no row
  EXPECT_TRUE(store->AddSweep(MakeSweep("s-new", 2, 2)));
}

}  // namespace
}  // namespace mbstream
