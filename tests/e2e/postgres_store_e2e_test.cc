// Two real servers on one PostgreSQL database (issue 16, the store): a run integrated by the
// first is listed by the second and its result fetched from it, identical. And --store is
// checked at the edge.
#include <gmock/gmock.h>

#include <filesystem>
#include <random>

#include "tests/common/postgres_cluster.h"
#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class PostgresStoreE2eTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() / ("mbstream-pg-e2e-" + std::to_string(std::random_device()()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static CommandOutcome Cli(const ServerProcess& server, const std::string& args) {
    return RunCommand(std::string(MBSTREAM_CLI) + " --server " + server.address() + " " + args);
  }
  fs::path dir_;
};

TEST_F(PostgresStoreE2eTest, SecondServerListsAndServesTheFirstServersRun) {
  if (const std::string why = PostgresCluster::Unavailable(); !why.empty()) {
    GTEST_SKIP() << "PostgreSQL test skipped: " << why;
  }
  PostgresCluster cluster;
  const std::string uri = cluster.CreateDatabase("mbstream");

  std::string run;
  {
    ServerProcess first(MBSTREAM_SERVER, (dir_ / "first").string(), {"--store", uri});
    const CommandOutcome started =
        Cli(first, "run single_pendulum --duration 1 --realtime 0 --watch");
    ASSERT_EQ(started.exit_code, 0) << started.output << ReadTextFile(first.log_path());
    run = started.output.substr(0, started.output.find('\n'));
    const CommandOutcome result = Cli(first, "result " + run + " --out " + (dir_ / "a").string());
    ASSERT_EQ(result.exit_code, 0) << result.output;
    // The second server starts while the first still runs: both on one database.
    ServerProcess second(MBSTREAM_SERVER, (dir_ / "second").string(), {"--store", uri});
    const CommandOutcome runs = Cli(second, "runs");
    ASSERT_EQ(runs.exit_code, 0) << runs.output;
    EXPECT_THAT(runs.output, HasSubstr(run));
    const CommandOutcome fetched = Cli(second, "result " + run + " --out " + (dir_ / "b").string());
    ASSERT_EQ(fetched.exit_code, 0) << fetched.output << ReadTextFile(second.log_path());
    EXPECT_THAT(ReadTextFile(second.log_path()), HasSubstr("data in " + uri));
  }
  const std::string joints = ReadTextFile((dir_ / "a" / "joints.csv").string());
  EXPECT_GT(joints.size(), 100u);
  EXPECT_EQ(ReadTextFile((dir_ / "b" / "joints.csv").string()), joints);
  EXPECT_EQ(ReadTextFile((dir_ / "b" / "tcp.csv").string()),
            ReadTextFile((dir_ / "a" / "tcp.csv").string()));
  EXPECT_THAT(ReadTextFile((dir_ / "b" / "stats.json").string()), HasSubstr("FINISHED"));
}

TEST_F(PostgresStoreE2eTest, BadStoreIsRefusedAtTheEdge) {
  const std::string server = std::string(MBSTREAM_SERVER) + " --listen 127.0.0.1:0 ";
  const CommandOutcome scheme = RunCommand(server + "--store mysql://a@b/c");
  EXPECT_EQ(scheme.exit_code, 2);
  EXPECT_THAT(scheme.output, HasSubstr("--store takes sqlite:DIRECTORY or postgresql://"));
  const CommandOutcome password = RunCommand(server + "--store postgresql://u:pw@h/db");
  EXPECT_EQ(password.exit_code, 2);
  EXPECT_THAT(password.output, HasSubstr("--store-password-file"));
  const CommandOutcome both =
      RunCommand(server + "--store sqlite:" + (dir_ / "x").string() + " --data " + dir_.string());
  EXPECT_NE(both.exit_code, 0);
  EXPECT_THAT(both.output, HasSubstr("excludes"));
  const CommandOutcome unreachable =
      RunCommand(server + "--store postgresql://mb@%2Fnonexistent-socket-dir/mbstream");
  EXPECT_EQ(unreachable.exit_code, 2);
  EXPECT_THAT(unreachable.output, HasSubstr("cannot connect to the store"));
}

}  // namespace
}  // namespace mbstream::testing
