// `mbstream delete`, `keep`, `retention --dry-run`, `storage` and `backup` as a user runs them
// against a real mbstream-server that keeps the newest ended run (--retain-runs 1, one pass at
// start only).
#include <gmock/gmock.h>

#include <filesystem>
#include <random>

#include "tests/common/cli_server_test.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

class DataCliTest : public CliServerTest {
 protected:
  void SetUp() override {
    CliServerTest::SetUp();
    StartServer({"--retain-runs", "1", "--retention-period-s", "86400"});
  }
  std::string EndedRun() {
    const CommandOutcome run = Cli("run irb1600 --spec models/irb1600/seed-run.json --watch");
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return run.output.substr(0, run.output.find('\n'));
  }
};

TEST_F(DataCliTest, KeepRetentionDryRunAndDelete) {
  const std::string first = EndedRun(), second = EndedRun(), third = EndedRun();
  ASSERT_EQ(first.substr(0, 2), "r-");

  CommandOutcome out = Cli("keep " + first);
  ASSERT_EQ(out.exit_code, 0) << out.output;
  EXPECT_THAT(out.output, HasSubstr(first + " kept"));
  out = Cli("retention --dry-run");  // kept: first; newest unkept: third; would go: second
  ASSERT_EQ(out.exit_code, 0) << out.output;
  EXPECT_THAT(out.output, HasSubstr("would delete 1 runs now"));
  EXPECT_THAT(out.output, HasSubstr(second));
  EXPECT_THAT(out.output, Not(HasSubstr(first)));
  EXPECT_THAT(out.output, Not(HasSubstr(third)));

  out = Cli("delete " + second + " " + third);
  ASSERT_EQ(out.exit_code, 0) << out.output;
  EXPECT_THAT(out.output, HasSubstr("deleted run " + second + " (FINISHED, 401 frames)"));
  EXPECT_THAT(out.output, HasSubstr("deleted run " + third));
  out = Cli("runs");
  EXPECT_THAT(out.output, HasSubstr(first));
  EXPECT_THAT(out.output, Not(HasSubstr(second)));
  out = Cli("result " + second + " --out " + (dir_ / "gone").string());
  EXPECT_EQ(out.exit_code, 2) << out.output;
  out = Cli("delete r-nothing");
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_THAT(out.output, HasSubstr("r-nothing"));

  out = Cli("delete");
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_THAT(out.output, HasSubstr("delete takes run ids"));
  out = Cli("delete --model irb1600 --with-runs");
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_THAT(out.output, HasSubstr("built in"));
  out = Cli("keep --off " + first);
  ASSERT_EQ(out.exit_code, 0) << out.output;
  EXPECT_THAT(out.output, HasSubstr("no longer kept"));
}

// `mbstream storage`, `health --service mbstream.new_runs` and `backup DIR`, then a second
// server started on the backup serves the runs.
TEST_F(DataCliTest, StorageBackupAndAServerOnTheBackup) {
  const std::string first = EndedRun(), second = EndedRun();
  CommandOutcome out = Cli("storage");
  ASSERT_EQ(out.exit_code, 0) << out.output;
  EXPECT_THAT(out.output, HasSubstr("store       sqlite " + (dir_ / "data").string()));
  EXPECT_THAT(out.output, HasSubstr("runs        FINISHED 2"));
  EXPECT_THAT(out.output, HasSubstr("free "));
  EXPECT_THAT(out.output, HasSubstr("(--min-free-mb 64.0 MiB)"));
  EXPECT_THAT(out.output, HasSubstr("would delete 1 runs"));  // --retain-runs 1
  EXPECT_THAT(out.output, HasSubstr("irb1600"));
  out = Cli("health --service mbstream.new_runs");
  EXPECT_EQ(out.exit_code, 0) << out.output;
  EXPECT_THAT(out.output, HasSubstr("SERVING"));

  const std::string backup = (dir_ / "backup").string();
  out = Cli("backup " + backup);
  ASSERT_EQ(out.exit_code, 0) << out.output;
  EXPECT_THAT(out.output, HasSubstr("backed up 2 runs into " + backup));
  out = Cli("backup " + backup);  // never over anything
  EXPECT_EQ(out.exit_code, 2) << out.output;
  EXPECT_THAT(out.output, HasSubstr("not empty"));

  ServerProcess restored(MBSTREAM_SERVER, backup, {});
  for (const std::string& run : {first, second}) {
    out = RunCommand(std::string(MBSTREAM_CLI) + " --server " + restored.address() + " result " +
                     run + " --out " + (dir_ / run).string());
    EXPECT_EQ(out.exit_code, 0) << out.output;
    EXPECT_TRUE(fs::exists(dir_ / run / "joints.csv"));
  }
}

}  // namespace
}  // namespace mbstream::testing
