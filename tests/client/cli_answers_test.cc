// Wrong answers to mistakes, as a newcomer makes them (issue 42, item 11): a usage error exits
// 2 (not CLI11's 105/106), a mistyped spec field or joint gets a "did you mean", a spec meant for
// another model names the joint that is not there, and simulate prints the same summary line
// as run --watch (with the energy error).
#include <gmock/gmock.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "shared/common/did_you_mean.h"
#include "tests/common/server_process.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

testing::CommandOutcome Mbstream(const std::string& args) {
  return testing::RunCommand(std::string(MBSTREAM_CLI) + " " + args + " 2>&1");
}

TEST(CliAnswersTest, DidYouMeanPicksTheCloseNameOrNone) {
  EXPECT_EQ(ClosestName("irb1601", {"chain100", "irb1600", "delta"}), "irb1600");
  EXPECT_EQ(ClosestName("duraton_s", {"duration_s", "drives"}), "duration_s");
  EXPECT_EQ(ClosestName("banana", {"irb1600", "delta"}), "");
  EXPECT_EQ(ClosestName("delta", {"delta"}), "");  // it is one of them
  EXPECT_EQ(DidYouMean("Delta2", {"delta"}), "; did you mean 'delta'?");
}

TEST(CliAnswersTest, AUsageErrorExitsTwo) {
  const testing::CommandOutcome missing =
      Mbstream("simulate models/irb1600/irb1600.urdf --spec /no/such/spec.json --out /tmp/x");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_THAT(missing.output, HasSubstr("--spec"));
  const testing::CommandOutcome unknown = Mbstream("runs --no-such-flag");
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
  EXPECT_EQ(Mbstream("--help").exit_code, 0);
}

class CliAnswersDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mbstream-cli-answers-" + std::to_string(std::random_device()()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(CliAnswersDirTest, AMistypedSpecFieldGetsADidYouMean) {
  std::ofstream(dir_ / "typo.json") << R"({"duraton_s": 2})";
  const testing::CommandOutcome typo =
      Mbstream("simulate models/irb1600/irb1600.urdf --spec " + (dir_ / "typo.json").string() +
               " --out " + (dir_ / "out").string());
  EXPECT_EQ(typo.exit_code, 2) << typo.output;
  EXPECT_THAT(typo.output, HasSubstr("did you mean 'duration_s'?"));
  std::ofstream(dir_ / "joint.json")
      << R"({"duration_s": 0.1, "drives": [{"joint": "crank_jiont", "passive": {}}]})";
  const testing::CommandOutcome joint =
      Mbstream("simulate models/linkages/four_bar.sdf --spec " + (dir_ / "joint.json").string() +
               " --out " + (dir_ / "out").string());
  EXPECT_EQ(joint.exit_code, 2) << joint.output;
  EXPECT_THAT(joint.output, HasSubstr("did you mean 'crank_joint'?"));
}

// The four-bar given the palletiser's spec: its first drive's joint axis1 is named.
TEST_F(CliAnswersDirTest, ASpecForAnotherModelNamesTheJointThatIsNotThere) {
  const testing::CommandOutcome run = Mbstream(
      "simulate models/linkages/four_bar.sdf --spec models/linkages/palletiser-driven.json --out " +
      (dir_ / "out").string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_THAT(run.output, HasSubstr("drives[0].joint: the model has no joint named 'axis1'"));
  EXPECT_THAT(run.output, HasSubstr("is the spec meant for another model?"));
}

TEST_F(CliAnswersDirTest, SimulatesSummaryLineHasTheEnergyError) {
  const testing::CommandOutcome run = Mbstream(
      "simulate models/irb1600/irb1600.urdf --spec models/irb1600/seed-servo.json "
      "--duration 0.2 --out " +
      (dir_ / "out").string());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("FINISHED: 5 frames to t = 0.2 s, formulation joint"));
  EXPECT_THAT(run.output, HasSubstr(", energy error "));
}

// Against a server: a mistyped model name gets the closest built-in; a --name that cannot be
// applied (the files are a model already stored under its own name) is said.
TEST_F(CliAnswersDirTest, AServerAnswersAMistypedModelAndAnIgnoredName) {
  testing::ServerProcess server(MBSTREAM_SERVER, (dir_ / "data").string());
  const std::string cli = "--server " + server.address() + " ";
  const testing::CommandOutcome typo =
      Mbstream(cli + "run irb1601 --spec models/irb1600/seed-run.json");
  EXPECT_EQ(typo.exit_code, 2) << typo.output;
  EXPECT_THAT(typo.output, HasSubstr("no model 'irb1601'"));
  EXPECT_THAT(typo.output, HasSubstr("did you mean 'irb1600'?"));
  const testing::CommandOutcome named = Mbstream(cli + "submit models/irb1600 --name my_arm");
  EXPECT_EQ(named.exit_code, 0) << named.output;
  EXPECT_THAT(named.output, HasSubstr("note: --name 'my_arm' not applied"));
  EXPECT_THAT(named.output, HasSubstr("already there as 'irb1600'"));
}

}  // namespace
}  // namespace mbstream
