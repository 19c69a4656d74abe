// The PostgreSQL store's own edges: --store locations checked before anything connects, a
// database that cannot be used refused with an InputError saying what to do, the schema
// migrated from the previous version, and a failing write rolled back whole.
#include <fstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <pqxx/pqxx>

#include "server/store/frame_chunks.h"
#include "server/store/postgres_schema.h"
#include "server/store/store_location.h"
#include "shared/common/check.h"
#include "tests/common/postgres_cluster.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;
using testing::MakeFrames;
using testing::MakeProbe;
using testing::MakeRun;
using testing::Same;
using testing::TempDirectory;

template <typename Call>
std::string InputErrorOf(Call&& call) {
  try {
    call();
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no InputError)";
}

TEST(StoreLocationTest, ParsesBothForms) {
  const StoreLocation sqlite = ParseStoreLocation("sqlite:/var/lib/mbstream");
  EXPECT_EQ(sqlite.kind, StoreLocation::Kind::kSqlite);
  EXPECT_EQ(sqlite.target, "/var/lib/mbstream");
  const StoreLocation postgres = ParseStoreLocation("postgresql://mb@db.example:5433/mbstream");
  EXPECT_EQ(postgres.kind, StoreLocation::Kind::kPostgresql);
  EXPECT_EQ(postgres.target, "postgresql://mb@db.example:5433/mbstream");
  EXPECT_EQ(ParseStoreLocation("postgres://mb@%2Frun%2Fpg/x").kind,
            StoreLocation::Kind::kPostgresql);
}

TEST(StoreLocationTest, RefusesWhatItCannotUseSayingWhatItTakes) {
  EXPECT_THAT(InputErrorOf([] { ParseStoreLocation("mysql://a@b/c"); }),
              HasSubstr("--store takes sqlite:DIRECTORY or postgresql://"));
  EXPECT_THAT(InputErrorOf([] { ParseStoreLocation("sqlite:"); }), HasSubstr("needs a directory"));
  EXPECT_THAT(InputErrorOf([] { ParseStoreLocation("postgresql://mb:secret@host/db"); }),
              HasSubstr("--store-password-file"));
  EXPECT_THAT(InputErrorOf([] { ParseStoreLocation("sqlite:a\nb"); }),
              HasSubstr("control character"));
}

TEST(StoreLocationTest, PasswordFileFirstLine) {
  TempDirectory temp;
  std::filesystem::create_directories(temp.path());
  const std::string file = (temp.path() / "password").string();
  std::ofstream(file) << "s3cr et\nignored\n";
  EXPECT_EQ(ReadStorePasswordFile(file), "s3cr et");
  std::ofstream(file) << "\n";
  EXPECT_THAT(InputErrorOf([&] { ReadStorePasswordFile(file); }), HasSubstr("is empty"));
  EXPECT_THAT(InputErrorOf([&] { ReadStorePasswordFile(file + ".missing"); }),
              HasSubstr("cannot read the store password file"));
}

TEST(StoreLocationTest, UnreachableDatabaseIsAnInputErrorNamingIt) {
  TempDirectory temp;  // a socket folder where no server listens
  std::filesystem::create_directories(temp.path());
  const std::string uri = "postgresql://mb@" + std::string("%2F") +
                          temp.path().filename().string() + "-nowhere/mbstream";
  const std::string message = InputErrorOf([&] { OpenStore(ParseStoreLocation(uri)); });
  EXPECT_THAT(message, HasSubstr("cannot connect to the store " + uri));
  EXPECT_THAT(message, HasSubstr("check that PostgreSQL is running"));
}

// The tests below need a PostgreSQL server of their own.
class PostgresStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const std::string why = testing::PostgresCluster::Unavailable(); !why.empty()) {
      GTEST_SKIP() << "PostgreSQL test skipped: " << why;
    }
    static int databases = 0;
    uri_ = testing::SharedPostgresCluster().CreateDatabase("pg_store_test_" +
                                                           std::to_string(databases++));
  }
  std::unique_ptr<Store> Open() const { return OpenStore(ParseStoreLocation(uri_)); }
  // Rows as every version up to 6 wrote them (the columns of version 1), in one transaction.
  void InsertOldRuns(const std::vector<v1::RunInfo>& runs) const {
    pqxx::connection raw(uri_);
    pqxx::work tx(raw);
    for (const v1::RunInfo& run : runs) {
      std::string bytes;
      ASSERT_TRUE(run.SerializeToString(&bytes));
      tx.exec_params(
          "INSERT INTO runs (id, model_id, state, created_unix_ms, info) "
          "VALUES ($1, $2, $3, $4, $5)",
          run.id(), run.model_id(), static_cast<int>(run.state()), run.created_unix_ms(),
          pqxx::binarystring(bytes));
    }
    tx.commit();
  }

  std::string uri_;
};

TEST_F(PostgresStoreTest, UnknownDatabaseIsAnInputError) {
  const std::string uri = uri_ + "_missing";
  EXPECT_THAT(InputErrorOf([&] { OpenStore(ParseStoreLocation(uri)); }),
              HasSubstr("cannot connect to the store " + uri));
}

TEST_F(PostgresStoreTest, AnotherProgramsDatabaseIsAnInputError) {
  {
    pqxx::connection raw(uri_);
    pqxx::work tx(raw);
    tx.exec("CREATE TABLE notes (text text)");
    tx.commit();
  }
  const std::string message = InputErrorOf([&] { Open(); });
  EXPECT_THAT(message, HasSubstr(uri_ + " holds 1 tables of another program"));
  EXPECT_THAT(message, HasSubstr("empty database"));
}

TEST_F(PostgresStoreTest, NewerSchemaVersionIsAnInputError) {
  Open();
  {
    pqxx::connection raw(uri_);
    pqxx::work tx(raw);
    tx.exec("UPDATE mbstream_schema SET version = 99");
    tx.commit();
  }
  const std::string message = InputErrorOf([&] { Open(); });
  EXPECT_THAT(message, HasSubstr("schema version 99"));
  EXPECT_THAT(message, HasSubstr("newer mbstream-server"));
}

TEST_F(PostgresStoreTest, VersionOneDatabaseIsMigratedKeepingItsRuns) {
  {  // what a version-1 server left: no probe set tables
    pqxx::connection raw(uri_);
    EnsurePostgresSchema(raw, uri_, 1);
    pqxx::work tx(raw);
    EXPECT_FALSE(tx.exec1("SELECT to_regclass('probe_sets') IS NOT NULL")[0].as<bool>());
    EXPECT_EQ(tx.exec1("SELECT version FROM mbstream_schema")[0].as<int>(), 1);
  }
  const v1::RunInfo run = MakeRun("r-1", v1::FINISHED, 1000);
  InsertOldRuns({run});  // a version-1 row, written as version 1 wrote it
  auto store = Open();
  ASSERT_TRUE(store->GetRun("r-1").has_value());
  EXPECT_TRUE(Same(*store->GetRun("r-1"), run));
  v1::ProbeSet set;
  set.set_id("ps-1");
  set.set_run_id("r-1");
  store->CreateProbeSet(set);
  store->AddProbeSetReports("ps-1", {MakeProbe("r-1", 0, "tip")});
  ASSERT_EQ(store->ListProbeSets("r-1").size(), 1u);
  EXPECT_EQ(store->ListProbeSets("r-1")[0].reports(), 1);
  pqxx::connection raw(uri_);
  pqxx::work tx(raw);
  EXPECT_EQ(tx.exec1("SELECT version FROM mbstream_schema")[0].as<int>(), kPostgresSchemaVersion);
  EXPECT_FALSE(tx.exec1("SELECT to_regclass('runs_by_state') IS NOT NULL")[0].as<bool>());
  EXPECT_TRUE(tx.exec1("SELECT to_regclass('runs_queue') IS NOT NULL")[0].as<bool>());
}

TEST_F(PostgresStoreTest, VersionSixDatabaseFindsItsSweepsAfterTheUpgrade) {
  {
    pqxx::connection raw(uri_);
    EnsurePostgresSchema(raw, uri_, 6);
  }
  v1::RunInfo cancelled = MakeRun("r-1", v1::CANCELLED, 1000);
  cancelled.set_sweep_id("s-a");
  cancelled.set_sweep_cancelled(true);  // where version 6 kept the mark: in the info
  v1::RunInfo queued = MakeRun("r-2", v1::QUEUED, 1001);
  queued.set_sweep_id("s-a");
  queued.set_sweep_point(1);
  // Version-6 rows, written as version 6 wrote them.
  InsertOldRuns({cancelled, queued, MakeRun("r-3", v1::FINISHED, 1002)});
  auto store = Open();
  const std::vector<v1::RunInfo> runs = store->ListSweepRuns("s-a");
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].id(), "r-1");
  EXPECT_TRUE(runs[0].sweep_cancelled());
  EXPECT_EQ(runs[1].id(), "r-2");
  EXPECT_FALSE(runs[1].sweep_cancelled());
  EXPECT_EQ(store->MarkSweepCancelled("s-a"), 1);  // r-2; r-1's mark was carried over
  pqxx::connection raw(uri_);
  pqxx::work tx(raw);
  EXPECT_TRUE(tx.exec1("SELECT to_regclass('runs_by_sweep') IS NOT NULL")[0].as<bool>());
}

// A trigger makes the second chunk's insert fail: the whole FinishRun rolls back, the error
// is an InternalError naming the operation and PostgreSQL's message, and the store stays
// usable.
TEST_F(PostgresStoreTest, FinishRunIsAtomic) {
  auto store = Open();
  const v1::RunInfo running = MakeRun("r-1", v1::RUNNING, 1000);
  store->PutRun(running);
  pqxx::connection raw(uri_);
  {
    pqxx::work tx(raw);
    tx.exec(
        "CREATE FUNCTION fail_second_chunk() RETURNS trigger AS $$ BEGIN "
        "IF NEW.chunk >= 1 THEN RAISE EXCEPTION 'injected disk failure'; END IF; RETURN NEW; "
        "END $$ LANGUAGE plpgsql; "
        "CREATE TRIGGER fail_second_chunk BEFORE INSERT ON frame_chunks "
        "FOR EACH ROW EXECUTE FUNCTION fail_second_chunk()");
    tx.commit();
  }
  try {
    store->FinishRun(MakeRun("r-1", v1::FINISHED, 1000), MakeFrames(kFramesPerChunk + 1, 6));
    FAIL() << "FinishRun did not throw";
  } catch (const InternalError& error) {
    EXPECT_THAT(error.what(), HasSubstr("finish run r-1 failed: "));
    EXPECT_THAT(error.what(), HasSubstr("injected disk failure"));
  }
  EXPECT_TRUE(Same(*store->GetRun("r-1"), running));
  EXPECT_TRUE(store->GetFrames("r-1").empty());
  {
    pqxx::work tx(raw);
    tx.exec("DROP TRIGGER fail_second_chunk ON frame_chunks");
    tx.commit();
  }
  const std::vector<v1::Frame> frames = MakeFrames(kFramesPerChunk + 1, 6);
  store->FinishRun(MakeRun("r-1", v1::FINISHED, 1000), frames);
  EXPECT_EQ(store->GetFrames("r-1").size(), frames.size());
}

// Probe reports go in multi-row statements: a batch larger than one statement holds, with
// duplicates inside it (the last wins), lands whole.
TEST_F(PostgresStoreTest, LargeProbeBatchWithDuplicates) {
  auto store = Open();
  std::vector<v1::ProbeReport> reports;
  for (int64_t seq = 0; seq < 4500; ++seq) reports.push_back(MakeProbe("r-1", seq, "tip"));
  v1::ProbeReport again = MakeProbe("r-1", 7, "tip");
  again.set_latency_us(1);
  reports.push_back(again);
  store->AddProbes(reports);
  const auto stored = store->GetProbes("r-1");
  ASSERT_EQ(stored.size(), 4500u);
  EXPECT_EQ(stored[7].latency_us(), 1);
  EXPECT_TRUE(Same(stored[4499], reports[4499]));
}

}  // namespace
}  // namespace mbstream
