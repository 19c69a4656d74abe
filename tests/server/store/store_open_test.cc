// Store::Open: creates what is missing, keeps everything across reopening, and refuses with a
// clear InputError what is not its database.
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/store/sqlite_connection.h"
#include "server/store/sqlite_statement.h"
#include "server/store/store.h"
#include "shared/common/check.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;
using testing::MakeBundle;
using testing::MakeFrames;
using testing::MakeModelInfo;
using testing::MakeProbe;
using testing::MakeRun;
using testing::Same;
using testing::TempDirectory;

std::string OpenError(const std::string& directory) {
  try {
    Store::Open(directory);
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no InputError)";
}

class StoreReopenTest : public testing::StoreBackendTest {};
INSTANTIATE_STORE_BACKENDS(StoreReopenTest);

TEST(StoreOpenTest, CreatesNestedDirectoryAndFile) {
  TempDirectory temp;
  const auto directory = temp.path() / "a" / "b";
  auto store = Store::Open(directory.string());
  EXPECT_TRUE(std::filesystem::is_regular_file(directory / "mbstream.sqlite3"));
  EXPECT_EQ(store->path(), (directory / "mbstream.sqlite3").string());
  EXPECT_TRUE(store->ListModels().empty());
  EXPECT_TRUE(store->ListRuns().empty());
}

TEST_P(StoreReopenTest, ReopenKeepsEverything) {
  const v1::ModelInfo model = MakeModelInfo("m-1", 1000);
  const v1::ModelBundle bundle = MakeBundle("arm", 2);
  const v1::RunInfo finished = MakeRun("r-1", v1::FINISHED, 2000);
  const v1::RunInfo running = MakeRun("r-2", v1::RUNNING, 3000);
  const std::vector<v1::Frame> frames = MakeFrames(5000, 6);
  {
    auto store = Open();
    ASSERT_TRUE(store->PutModel(model, bundle));
    store->FinishRun(finished, frames);
    store->PutRun(running);
    store->AddProbes({MakeProbe("r-1", 3, "tip")});
  }
  auto store = Open();
  ASSERT_EQ(store->ListModels().size(), 1u);
  EXPECT_TRUE(Same(store->ListModels()[0], model));
  ASSERT_TRUE(store->GetModelBundle("m-1").has_value());
  EXPECT_TRUE(Same(*store->GetModelBundle("m-1"), bundle));
  ASSERT_EQ(store->ListRuns().size(), 2u);
  EXPECT_TRUE(Same(*store->GetRun("r-1"), finished));
  EXPECT_TRUE(Same(*store->GetRun("r-2"), running));
  const std::vector<v1::Frame> loaded = store->GetFrames("r-1");
  ASSERT_EQ(loaded.size(), frames.size());
  EXPECT_TRUE(Same(loaded.back(), frames.back()));
  ASSERT_EQ(store->GetProbes("r-1").size(), 1u);
}

TEST(StoreOpenTest, DirectoryUnderAFileIsAnInputErrorNamingIt) {
  TempDirectory temp;
  std::filesystem::create_directories(temp.path());
  const auto file = temp.path() / "plain-file";
  std::ofstream(file) << "not a directory\n";
  const std::string directory = (file / "data").string();
  const std::string message = OpenError(directory);
  EXPECT_THAT(message, HasSubstr("cannot create the data directory " + directory));
  EXPECT_THAT(message, HasSubstr("--data"));
}

TEST(StoreOpenTest, DataPathThatIsAFileIsAnInputError) {
  TempDirectory temp;
  std::filesystem::create_directories(temp.path());
  const auto file = temp.path() / "plain-file";
  std::ofstream(file) << "x";
  EXPECT_THAT(OpenError(file.string()), HasSubstr("cannot create the data directory"));
}

TEST(StoreOpenTest, GarbageFileIsAnInputErrorNamingIt) {
  TempDirectory temp;
  std::filesystem::create_directories(temp.path());
  const auto file = temp.path() / "mbstream.sqlite3";
  {
    std::ofstream out(file, std::ios::binary);
    for (int i = 0; i < 200; ++i) out << "this is not a database, just some text. ";
  }
  const auto size_before = std::filesystem::file_size(file);
  const std::string message = OpenError(temp.str());
  EXPECT_THAT(message, HasSubstr(file.string() + " is not an mbstream database"));
  EXPECT_THAT(message, HasSubstr("move the file away"));
  EXPECT_EQ(std::filesystem::file_size(file), size_before);  // left untouched
}

TEST(StoreOpenTest, AnotherProgramsSqliteDatabaseIsAnInputError) {
  TempDirectory temp;
  std::filesystem::create_directories(temp.path());
  {
    auto other = SqliteConnection::Open((temp.path() / "mbstream.sqlite3").string());
    other.Exec("CREATE TABLE notes (text TEXT)", "create");
  }
  EXPECT_THAT(OpenError(temp.str()), HasSubstr("another program, not an mbstream database"));
}

TEST(StoreOpenTest, VersionThreeStoreLosesTheIndexByStateAndKeepsItsRuns) {
  TempDirectory temp;
  const std::string file = (temp.path() / Store::kFileName).string();
  auto indexes = [&] {
    auto raw = SqliteConnection::Open(file);
    SqliteStatement query(raw, "SELECT count(*) FROM sqlite_master WHERE name = 'runs_by_state'",
                          "count");
    EXPECT_TRUE(query.Step());
    const int64_t count = query.ColumnInt64(0);
    query.Reset();
    return count;
  };
  {
    auto store = Store::Open(temp.str());
    store->PutRun(MakeRun("r-1", v1::QUEUED, 1));
  }
  EXPECT_EQ(indexes(), 0);
  {  // what a version-3 server left
    auto raw = SqliteConnection::Open(file);
    raw.Exec("CREATE INDEX runs_by_state ON runs (state); " + std::string(kDropFrameFileColumns) +
                 "PRAGMA user_version = 3",
             "make a version-3 store");
  }
  EXPECT_EQ(indexes(), 1);
  auto store = Store::Open(temp.str());
  EXPECT_EQ(indexes(), 0);
  ASSERT_TRUE(store->GetRun("r-1"));
  RunLease lease;
  lease.replica = "replica-a";
  lease.now_unix_ms = 5000;
  lease.expires_unix_ms = 15000;
  const auto claimed = store->ClaimQueuedRun(lease);  // found by its state
  ASSERT_TRUE(claimed.has_value());
  EXPECT_EQ(claimed->id(), "r-1");
}

TEST(StoreOpenTest, NewerSchemaVersionIsAnInputError) {
  TempDirectory temp;
  Store::Open(temp.str());
  {
    auto raw = SqliteConnection::Open((temp.path() / "mbstream.sqlite3").string());
    raw.Exec("PRAGMA user_version = 99", "raise version");
  }
  const std::string message = OpenError(temp.str());
  EXPECT_THAT(message, HasSubstr("schema version 99"));
  EXPECT_THAT(message, HasSubstr("newer mbstream-server"));
}

}  // namespace
}  // namespace mbstream
