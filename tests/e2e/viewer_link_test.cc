// Real server + real offscreen viewer (Xvfb) + CLI: the viewer answers every frame of a run
// with a probe equal to the server's TCP; its errors name what is wrong.
#include <gmock/gmock.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>

#include "tests/common/cli_server_test.h"
#include "tests/common/csv_rows.h"
#include "tests/e2e/probe_checks.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class ViewerLinkTest : public CliServerTest {
 protected:
  void SetUp() override {
    CliServerTest::SetUp();
    StartServer();
  }
  std::string Viewer(const std::string& args) {
    return "scripts/with-xvfb.sh " + std::string(MBSTREAM_VIEWER) + " --server " +
           server_->address() + " --offscreen --size 320x240 " + args;
  }
};

TEST_F(ViewerLinkTest, FollowingViewerAnswersEveryFrameWithTheTcp) {
  const fs::path log = dir_ / "viewer.log";
  ASSERT_EQ(
      RunCommand(Viewer("--follow --exit-after-runs 1 > " + log.string() + " 2>&1 &")).exit_code,
      0);
  ASSERT_TRUE(WaitForLineIn(log.string(), "subscribed to")) << ReadTextFile(log.string());
  const CommandOutcome run =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --realtime 5 --watch");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string run_id = run.output.substr(0, run.output.find('\n'));
  ASSERT_TRUE(WaitForLineIn(log.string(), "viewer done")) << ReadTextFile(log.string());
  const CommandOutcome result = Cli("result " + run_id + " --out " + (dir_ / "out").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  ExpectProbesMatchTcp(dir_ / "out", 0, 400);
}

// A mechanism with closed loops (issue 31): the Delta robot, submitted as SDFormat, runs
// kinematically on the server (Newton on its five cut ball joints at each frame); the viewer
// draws it from the same SDFormat reading, poses its 18 tree joints from each frame (whose
// cut joints' columns follow the tree's) and answers with its platform's centre, which
// equals the server's TCP at every frame.
TEST_F(ViewerLinkTest, FollowingViewerShowsALiveLoopRunOfTheDeltaAndAnswersWithItsTcp) {
  const CommandOutcome submit = Cli("submit models/linkages/delta.sdf --name delta");
  ASSERT_EQ(submit.exit_code, 0) << submit.output;
  const fs::path log = dir_ / "viewer.log";
  ASSERT_EQ(
      RunCommand(Viewer("--follow --exit-after-runs 1 > " + log.string() + " 2>&1 &")).exit_code,
      0);
  ASSERT_TRUE(WaitForLineIn(log.string(), "subscribed to")) << ReadTextFile(log.string());
  const CommandOutcome run =
      Cli("run delta --spec models/linkages/delta-driven.json --realtime 5 --watch");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string run_id = run.output.substr(0, run.output.find('\n'));
  ASSERT_TRUE(WaitForLineIn(log.string(), "viewer done")) << ReadTextFile(log.string());
  const std::string viewer_log = ReadTextFile(log.string());
  EXPECT_THAT(viewer_log, HasSubstr("showing scene 'delta'"));
  EXPECT_THAT(viewer_log, ::testing::Not(HasSubstr("[error]")));
  SCOPED_TRACE(viewer_log);
  const CommandOutcome result = Cli("result " + run_id + " --out " + (dir_ / "out").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  ExpectProbesMatchTcp(dir_ / "out", 0, 200);
}

// Contacts on the wire (issue 44): a viewer started with --contacts asks for each frame's
// contacts and draws them; a box resting on a plane touches it at four corners in every frame.
TEST_F(ViewerLinkTest, FollowingViewerWithContactsDrawsEveryFramesContacts) {
  const CommandOutcome submit = Cli("submit tests/data/contact/box_resting.sdf --name box");
  ASSERT_EQ(submit.exit_code, 0) << submit.output;
  const fs::path log = dir_ / "viewer.log";
  ASSERT_EQ(
      RunCommand(Viewer("--follow --contacts --exit-after-runs 1 > " + log.string() + " 2>&1 &"))
          .exit_code,
      0);
  ASSERT_TRUE(WaitForLineIn(log.string(), "subscribed to")) << ReadTextFile(log.string());
  const CommandOutcome run =
      Cli("run box --duration 1 --output-interval 0.05 --realtime 2 --watch");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ASSERT_TRUE(WaitForLineIn(log.string(), "viewer done")) << ReadTextFile(log.string());
  const std::string viewer_log = ReadTextFile(log.string());
  // Of the 21 frames, every one after the first (at t = 0 the box just touches, depth 0) has
  // the four corners.
  const std::smatch drawn = [&] {
    std::smatch m;
    std::regex_search(viewer_log, m,
                      std::regex("contacts: drawn in (\\d+) frames, at most (\\d+)"));
    return m;
  }();
  ASSERT_EQ(drawn.size(), 3u) << viewer_log;
  EXPECT_GE(std::stoi(drawn[1]), 20) << viewer_log;
  EXPECT_EQ(std::stoi(drawn[2]), 4) << viewer_log;
  EXPECT_THAT(viewer_log, ::testing::Not(HasSubstr("[error]")));
}

TEST_F(ViewerLinkTest, RunModeJoinsARunningRunAndAnswersFromThenOn) {
  const CommandOutcome started =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --duration 600 --realtime 1");
  ASSERT_EQ(started.exit_code, 0) << started.output;
  const std::string run = started.output.substr(0, started.output.find('\n'));
  const fs::path log = dir_ / "viewer.log";
  ASSERT_EQ(RunCommand(Viewer("--run " + run + " > " + log.string() + " 2>&1 &")).exit_code, 0);
  ASSERT_TRUE(WaitForLineIn(log.string(), "showing scene 'IRB1600'")) << ReadTextFile(log.string());
  // Cancel once the viewer has answered a frame of the run it joined.
  ASSERT_TRUE(WaitForLineIn(log.string(), "answering with probe reports from frame"))
      << ReadTextFile(log.string());
  ASSERT_EQ(Cli("cancel " + run).exit_code, 0);  // the viewer sees the end and exits
  ASSERT_TRUE(WaitForLineIn(log.string(), "viewer done")) << ReadTextFile(log.string());
  const CommandOutcome result = Cli("result " + run + " --out " + (dir_ / "out").string());
  ASSERT_EQ(result.exit_code, 1) << result.output;  // CANCELLED
  const auto probes = ReadCsv(dir_ / "out" / "probes.csv");
  const auto tcp = ReadCsv(dir_ / "out" / "tcp.csv");
  ASSERT_FALSE(probes.empty());
  ExpectProbesMatchTcp(dir_ / "out", std::stoll(probes.front()[0]),
                       static_cast<int64_t>(tcp.size()) - 1);
}

// SIGTERM while frames are flowing: the viewer stops its stream and exits 0 (it used to abort
// now and then, cancelling a stream context that was being destroyed).
TEST_F(ViewerLinkTest, SigtermWhileFollowingARunExitsCleanly) {
  const CommandOutcome started =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --duration 600 --realtime 1");
  ASSERT_EQ(started.exit_code, 0) << started.output;
  const std::string run = started.output.substr(0, started.output.find('\n'));
  for (int attempt = 0; attempt < 3; ++attempt) {
    const fs::path log = dir_ / ("viewer-" + std::to_string(attempt) + ".log");
    ASSERT_EQ(RunCommand("(" + Viewer("--follow") + "; echo \"viewer exit $?\") > " + log.string() +
                         " 2>&1 &")
                  .exit_code,
              0);
    ASSERT_TRUE(WaitForLineIn(log.string(), "answering with probe reports from frame"))
        << ReadTextFile(log.string());
    // The viewer itself, not with-xvfb.sh (whose command line starts with the shell).
    ASSERT_EQ(RunCommand("pkill -TERM -f '^" + std::string(MBSTREAM_VIEWER) + " --server " +
                         server_->address() + " '")
                  .exit_code,
              0);
    const std::optional<std::string> exit = WaitForLineIn(log.string(), "viewer exit ");
    ASSERT_TRUE(exit) << ReadTextFile(log.string());
    EXPECT_EQ(*exit, "0") << ReadTextFile(log.string());
    EXPECT_THAT(ReadTextFile(log.string()), HasSubstr("SIGTERM received"));
  }
  Cli("cancel " + run);
}

TEST_F(ViewerLinkTest, SceneThatDoesNotFitTheModelIsAnErrorNamingBoth) {
  const CommandOutcome started = Cli("run single_pendulum --realtime 2");
  ASSERT_EQ(started.exit_code, 0) << started.output;
  const std::string run = started.output.substr(0, started.output.find('\n'));
  const CommandOutcome viewer =
      RunCommand(Viewer("--run " + run + " --scene models/irb1600/irb1600.scene"));
  EXPECT_EQ(viewer.exit_code, 1);
  EXPECT_THAT(viewer.output, HasSubstr("scene 'IRB1600' has 6 joints but model 'single_pendulum'"));
  EXPECT_THAT(viewer.output, HasSubstr("has 1"));
  Cli("cancel " + run);
}

TEST_F(ViewerLinkTest, UnknownRunIsAClearError) {
  const CommandOutcome viewer = RunCommand(Viewer("--run r-nosuch"));
  EXPECT_EQ(viewer.exit_code, 1);
  EXPECT_THAT(viewer.output, HasSubstr("no run 'r-nosuch'"));
}

TEST_F(ViewerLinkTest, WithoutADisplayItSaysToUseXvfb) {
  const CommandOutcome viewer = RunCommand("env -u DISPLAY " + std::string(MBSTREAM_VIEWER) +
                                           " --server " + server_->address() + " --follow");
  EXPECT_EQ(viewer.exit_code, 2);
  EXPECT_THAT(viewer.output, HasSubstr("xvfb-run"));
}

}  // namespace
}  // namespace mbstream::testing
