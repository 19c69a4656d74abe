// SqliteCheckpointer: the WAL is copied into the database file on the checkpointer's thread,
// not in the writer's commits, and the file stays whole across the checkpoints.
#include "server/store/sqlite_checkpointer.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <string>

#include "server/store/sqlite_statement.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;

// The thresholds are bytes of WAL, whatever the database's page size.
class SqliteCheckpointerTest : public ::testing::TestWithParam<int> {};
INSTANTIATE_TEST_SUITE_P(PageSizes, SqliteCheckpointerTest, ::testing::Values(4096, 16384));

TEST_P(SqliteCheckpointerTest, CopiesTheWalIntoTheDatabaseOnItsOwnThread) {
  testing::TempDirectory temp;
  fs::create_directories(temp.path());
  const std::string path = (temp.path() / "db.sqlite3").string();
  SqliteConnection db = SqliteConnection::Open(path);
  db.Exec("PRAGMA page_size = " + std::to_string(GetParam()) +
              "; PRAGMA journal_mode = WAL; CREATE TABLE blobs (id INTEGER PRIMARY KEY, data BLOB)",
          "set up");
  SqliteCheckpointer checkpointer(db);
  const std::string blob(400 << 10, 'x');  // about 100 pages of 4 KB per commit
  constexpr int kCommits = 30;             // 3 times the background threshold
  SqliteStatement insert(db, "INSERT INTO blobs (data) VALUES (?1)", "insert");
  for (int i = 0; i < kCommits; ++i) {
    insert.BindBlob(1, blob);
    insert.Run();
    insert.Reset();
  }
  EXPECT_GE(checkpointer.WaitIdle(), 1);
  // What the checkpoints copied is in the database file itself (a WAL-only database file
  // holds the schema page alone), and every row is there. (12 MB of WAL: a threshold of
  // 1,000 pages would never be reached with pages of 16 KB.)
  EXPECT_GE(fs::file_size(path), static_cast<uintmax_t>(SqliteCheckpointer::kBackgroundBytes));
  SqliteStatement count(db, "SELECT count(*), sum(length(data)) FROM blobs", "count");
  ASSERT_TRUE(count.Step());
  EXPECT_EQ(count.ColumnInt64(0), kCommits);
  EXPECT_EQ(count.ColumnInt64(1),
            static_cast<int64_t>(kCommits) * static_cast<int64_t>(blob.size()));
}

}  // namespace
}  // namespace mbstream
