// `mbstream delete`, `keep` and `retention --dry-run` as a user runs them against a real
// mbstream-server that keeps the newest ended run (--retain-runs 1, one pass at start only).
#include <gmock/gmock.h>

#include <filesystem>
#include <random>

#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

class DataCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device random;
    dir_ = fs::temp_directory_path() / ("mbstream-data-cli-" + std::to_string(random()));
    fs::create_directories(dir_);
    server_ = std::make_unique<ServerProcess>(
        MBSTREAM_SERVER, (dir_ / "data").string(),
        std::vector<std::string>{"--retain-runs", "1", "--retention-period-s", "86400"});
  }
  void TearDown() override {
    server_.reset();
    fs::remove_all(dir_);
  }
  CommandOutcome Cli(const std::string& args) {
    return RunCommand(std::string(MBSTREAM_CLI) + " --server " + server_->address() + " " + args);
  }
  std::string EndedRun() {
    const CommandOutcome run = Cli("run irb1600 --spec models/irb1600/seed-run.json --watch");
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return run.output.substr(0, run.output.find('\n'));
  }

  fs::path dir_;
  std::unique_ptr<ServerProcess> server_;
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

}  // namespace
}  // namespace mbstream::testing
