// The viewer and its X display (issue 36, item 9), with a real server and real Xvfb: the
// README's own command (xvfb-run -a, whose Xvfb resets when its last client leaves) follows a
// burst of quick runs, and a viewer whose X server is killed goes on answering probes.
#include <gmock/gmock.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <random>
#include <thread>

#include "tests/common/cli_server_test.h"
#include "tests/e2e/probe_checks.h"
#include "tests/viewer/xvfb_server.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

class ViewerDisplayTest : public CliServerTest {
 protected:
  void SetUp() override {
    CliServerTest::SetUp();
    StartServer();
  }
  void TearDown() override {
    // A viewer still running (a test that failed) is stopped with what it started (Xvfb).
    const std::string group = ReadTextFile((dir_ / "viewer.pgid").string());
    if (!group.empty()) kill(-std::stoi(group), SIGTERM);
    CliServerTest::TearDown();
  }
  std::string Cli() const { return std::string(MBSTREAM_CLI) + " --server " + server_->address(); }
  // Starts `command` (a viewer; no single quotes) in the background, in a process group of its
  // own: its output, then "viewer exit CODE", go to `log`.
  void StartViewer(const std::string& command, const fs::path& log) {
    ASSERT_EQ(
        RunCommand("setsid sh -c 'echo $$ > " + (dir_ / "viewer.pgid").string() + "; (" + command +
                   "; echo \"viewer exit $?\") > " + log.string() + " 2>&1' > /dev/null 2>&1 &")
            .exit_code,
        0);
  }
};

// Waits up to 30 s for `path` to exist.
bool WaitForFile(const fs::path& path) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!fs::exists(path)) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

int CountLines(const std::string& text, const std::string& marker) {
  int count = 0;
  for (size_t at = text.find(marker); at != std::string::npos; at = text.find(marker, at + 1)) {
    ++count;
  }
  return count;
}

// The README's command, as the issue ran it while a sweep started several runs a second: the
// viewer aborted ("bad X server connection ... Aborting") about 8.5 s in, each time, when a
// run's new window connected while xvfb-run's Xvfb was resetting after the last window left.
// The abort depends on timing (the old viewer survived 60 runs in 4 of 14 tries); what
// caused it does not: Xvfb's audit log (-audit 4, xvfb-run's default screen kept) shows every
// client connection, and the viewer must make exactly one.
TEST_F(ViewerDisplayTest, ReadmeCommandFollowsABurstOfQuickRunsOnOneXConnection) {
  constexpr int kRuns = 60;
  const fs::path log = dir_ / "viewer.log";
  const fs::path xvfb_log = dir_ / "xvfb.log";
  // -n: where xvfb-run -a starts looking for a free display, away from other sessions' Xvfb.
  const int first_display = 100 + static_cast<int>(std::random_device()() % 800);
  StartViewer("xvfb-run -a -n " + std::to_string(first_display) + " -e " + xvfb_log.string() +
                  " -s \"-screen 0 1280x1024x24 -audit 4\" " + MBSTREAM_VIEWER + " --server " +
                  server_->address() + " --follow --offscreen --exit-after-runs " +
                  std::to_string(kRuns),
              log);
  ASSERT_TRUE(WaitForLineIn(log.string(), "subscribed to", 60)) << ReadTextFile(log.string());
  const CommandOutcome burst =
      RunCommand("for i in $(seq " + std::to_string(kRuns) + "); do " + Cli() +
                 " run single_pendulum --duration 0.2 > /dev/null || exit 1; done");
  ASSERT_EQ(burst.exit_code, 0) << burst.output;
  const std::optional<std::string> exit = WaitForLineIn(log.string(), "viewer exit ", 120);
  const std::string text = ReadTextFile(log.string());
  ASSERT_TRUE(exit) << text;
  EXPECT_EQ(*exit, "0") << text;
  EXPECT_THAT(text, HasSubstr("viewer done: " + std::to_string(kRuns) + " runs"));
  EXPECT_EQ(CountLines(text, "showing scene"), kRuns) << text;
  EXPECT_THAT(text, Not(HasSubstr("Aborting")));
  const std::string audit = ReadTextFile(xvfb_log.string());
  EXPECT_EQ(CountLines(audit, " connected from "), 1) << audit;
}

// The X server is killed between two runs under an offscreen viewer (the README's mode, where
// drawing sends nothing to the X server): the viewer logs it, draws nothing more, answers
// every frame of the next run with its probe, and exits 0. (In a window a draw talks to the
// X server, and one that dies during it can crash Mesa's rasteriser: viewer/README.md.)
TEST_F(ViewerDisplayTest, KilledXServerIsSurvivedAndProbesGoOn) {
  viewer::testing::XvfbServer xvfb;
  ASSERT_TRUE(xvfb.Start()) << "Xvfb does not start (Debian package xvfb)";
  const fs::path log = dir_ / "viewer.log";
  StartViewer("DISPLAY=" + xvfb.display() + " " + MBSTREAM_VIEWER + " --server " +
                  server_->address() +
                  " --follow --offscreen --size 320x240 --exit-after-runs 2 --snapshots " +
                  (dir_ / "png").string(),
              log);
  ASSERT_TRUE(WaitForLineIn(log.string(), "subscribed to")) << ReadTextFile(log.string());
  const std::string run = " run irb1600 --spec models/irb1600/seed-run.json --realtime 20 --watch";
  const CommandOutcome first = RunCommand(Cli() + run);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  ASSERT_TRUE(WaitForLineIn(log.string(), "ended: FINISHED")) << ReadTextFile(log.string());
  ASSERT_TRUE(WaitForFile(dir_ / "png" / "frame_00001.png")) << "it never drew";

  xvfb.Kill();
  ASSERT_TRUE(WaitForLineIn(log.string(), "the X display " + xvfb.display() + " is lost"))
      << ReadTextFile(log.string());
  const auto snapshots = [&] {
    return std::distance(fs::directory_iterator(dir_ / "png"), fs::directory_iterator());
  };
  const auto drawn = snapshots();
  const CommandOutcome second = RunCommand(Cli() + run);
  ASSERT_EQ(second.exit_code, 0) << second.output;
  const std::string run_id = second.output.substr(0, second.output.find('\n'));
  const std::optional<std::string> exit = WaitForLineIn(log.string(), "viewer exit ");
  const std::string text = ReadTextFile(log.string());
  ASSERT_TRUE(exit) << text;
  EXPECT_EQ(*exit, "0") << text;
  EXPECT_THAT(text, HasSubstr("viewer done: 2 runs"));
  EXPECT_EQ(snapshots(), drawn);  // nothing drawn since
  const CommandOutcome result =
      RunCommand(Cli() + " result " + run_id + " --out " + (dir_ / "out").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  ExpectProbesMatchTcp(dir_ / "out", 0, 400);
}

}  // namespace
}  // namespace mbstream::testing
