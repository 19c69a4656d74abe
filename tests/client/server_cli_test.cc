// mbstream-server and the mbstream CLI as a user runs them: real processes on loopback,
// real files, exit codes; a crash and a restart; reproducible results.
#include <gmock/gmock.h>
#include <sys/wait.h>

#include <csignal>

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "tests/common/cli_server_test.h"
#include "tests/common/sanitized_build.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

class ServerCliTest : public CliServerTest {};

TEST_F(ServerCliTest, SubmitRunWatchOutGivesTheSameFilesAsSimulate) {
  StartServer();
  const CommandOutcome submit = Cli("submit models/irb1600");
  ASSERT_EQ(submit.exit_code, 0) << submit.output;
  EXPECT_THAT(submit.output, HasSubstr("m-"));
  EXPECT_THAT(submit.output, HasSubstr("6 joints"));

  const CommandOutcome run =
      Cli("run irb1600 --spec models/irb1600/seed-servo.json --watch --out " + Out("server"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string run_id = FirstLine(run.output);
  EXPECT_EQ(run_id.substr(0, 2), "r-");
  EXPECT_THAT(run.output, HasSubstr("FINISHED"));

  const CommandOutcome simulate = RunCommand(
      std::string(MBSTREAM_CLI) +
      " simulate models/irb1600/irb1600.urdf --spec models/irb1600/seed-servo.json --out " +
      Out("local"));
  ASSERT_EQ(simulate.exit_code, 0) << simulate.output;
  for (const char* file : {"joints.csv", "velocities.csv", "tcp.csv", "torques.csv"}) {
    const std::string served = ReadFile(dir_ / "server" / file);
    EXPECT_FALSE(served.empty()) << file;
    EXPECT_EQ(served, ReadFile(dir_ / "local" / file)) << file << " differs";
  }
  const std::string stats = ReadFile(dir_ / "server" / "stats.json");
  EXPECT_THAT(stats, HasSubstr("\"run_id\": \"" + run_id + "\""));
  EXPECT_THAT(stats, HasSubstr("\"model_id\": \"m-"));
  EXPECT_THAT(stats, HasSubstr("\"mbstream_version\""));
  EXPECT_THAT(stats, HasSubstr("\"pd_servo\""));

  // `result` fetches the same files again.
  const CommandOutcome result = Cli("result " + run_id + " --out " + Out("again"));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(ReadFile(dir_ / "again" / "torques.csv"), ReadFile(dir_ / "server" / "torques.csv"));

  const CommandOutcome runs = Cli("runs");
  EXPECT_THAT(runs.output, HasSubstr(run_id));
  EXPECT_THAT(runs.output, HasSubstr("FINISHED"));
  EXPECT_EQ(server_->Stop(), 0);  // SIGINT: a clean exit
}

TEST_F(ServerCliTest, ConcurrentRunsAreBitIdentical) {
  StartServer({"--workers", "2"});
  std::string command = "(";
  for (int i = 0; i < 3; ++i) {
    command += std::string(MBSTREAM_CLI) + " --server " + server_->address() +
               " run irb1600 --spec models/irb1600/seed-servo.json --out " +
               Out("run" + std::to_string(i)) + " & ";
  }
  command += "wait)";
  ASSERT_EQ(RunCommand(command).exit_code, 0);
  for (int i = 1; i < 3; ++i) {
    for (const char* file : {"joints.csv", "torques.csv"}) {
      const std::string first = ReadFile(dir_ / "run0" / file);
      EXPECT_FALSE(first.empty());
      EXPECT_EQ(ReadFile(dir_ / ("run" + std::to_string(i)) / file), first) << file;
    }
  }
}

TEST_F(ServerCliTest, KilledServerRestartsWithEveryModelAndRunAndTheInterruptedOne) {
  StartServer();
  // A model of our own (a built-in's content under another name would be the built-in).
  std::ofstream(dir_ / "mine.urdf")
      << ReadFile("models/pendulum/double_pendulum.urdf") << "<!-- mine -->\n";
  ASSERT_EQ(Cli("submit " + Out("mine.urdf") + " --name mine").exit_code, 0);
  const CommandOutcome finished =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --out " + Out("finished"));
  ASSERT_EQ(finished.exit_code, 0) << finished.output;
  const std::string finished_id = FirstLine(finished.output);
  const CommandOutcome slow =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --duration 600 --realtime 1");
  ASSERT_EQ(slow.exit_code, 0) << slow.output;
  const std::string slow_id = FirstLine(slow.output);
  ASSERT_TRUE(WaitForLineIn(server_->log_path(), "run " + slow_id + " started"));
  server_->Kill();  // a crash mid-run

  StartServer();
  const CommandOutcome models = Cli("models");
  EXPECT_THAT(models.output, HasSubstr("mine"));
  const CommandOutcome runs = Cli("runs");
  ASSERT_EQ(runs.exit_code, 0) << runs.output;
  EXPECT_THAT(runs.output, ::testing::ContainsRegex(finished_id + " +irb1600 +FINISHED"));
  EXPECT_THAT(runs.output, ::testing::ContainsRegex(slow_id + " +irb1600 +INTERRUPTED"));
  const CommandOutcome result = Cli("result " + finished_id + " --out " + Out("after"));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(ReadFile(dir_ / "after" / "joints.csv"), ReadFile(dir_ / "finished" / "joints.csv"));
  // The interrupted run is never shown as finished: its result says so (exit code 1).
  EXPECT_EQ(Cli("result " + slow_id + " --out " + Out("interrupted")).exit_code, 1);
  EXPECT_THAT(ReadFile(dir_ / "interrupted" / "stats.json"),
              HasSubstr("\"status\": \"INTERRUPTED\""));
}

// A second signal during a drain's grace period ends the server at once (status 1): the run
// the drain waits for is cut short, and the next start marks it INTERRUPTED.
TEST_F(ServerCliTest, ASecondSignalDuringADrainEndsTheServerAtOnce) {
  StartServer({"--grace-s", "600"});
  const CommandOutcome slow =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --duration 600 --realtime 1");
  ASSERT_EQ(slow.exit_code, 0) << slow.output;
  const std::string slow_id = FirstLine(slow.output);
  ASSERT_TRUE(WaitForLineIn(server_->log_path(), "run " + slow_id + " started"));
  ASSERT_EQ(kill(server_->pid(), SIGTERM), 0);
  ASSERT_TRUE(WaitForLineIn(server_->log_path(), "signal SIGTERM received"));
  const int status = server_->Stop();  // SIGINT, the second signal
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_THAT(ReadFile(server_->log_path()), HasSubstr("a second signal; exiting"));

  StartServer();
  const CommandOutcome runs = Cli("runs");
  ASSERT_EQ(runs.exit_code, 0) << runs.output;
  EXPECT_THAT(runs.output, ::testing::ContainsRegex(slow_id + " +irb1600 +INTERRUPTED"));
}

// The sweep's id in `mbstream sweep`'s output ("sweep s-...: ..."), or "" when it is missing.
std::string SweepIdOf(const std::string& output) {
  const size_t at = output.find("sweep s-");
  if (at == std::string::npos) return "";
  return output.substr(at + 6, output.find(':', at) - at - 6);
}

std::string LastLine(const std::string& text) {
  std::string last;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) last = line;
  }
  return last;
}

// Budgets, warnings and trust through the server: the typo spec is warned about when the
// run starts, stops at the server's step cap, and exits 1; a spec asking for more CPU than
// the cap is told so; an untrusted finished run exits 4 unless --accept-untrusted.
TEST_F(ServerCliTest, BudgetsWarningsAndTrustOnTheServer) {
  // In a sanitizer build a step of the typo run costs about 2.5 ms of CPU: 50,000 steps would
  // outlast the 30 s CPU cap, so the step cap there is 5,000 (still the one that runs out).
  const std::string steps = testing::kSanitizedBuild ? "5000" : "50000";
  StartServer({"--max-run-steps", steps, "--max-run-cpu-s", "30"});
  std::string spec = ReadFile("tests/data/typo-servo.json");
  spec.insert(spec.find('{') + 1, "\n  \"max_cpu_s\": 1000,");
  std::ofstream(dir_ / "typo.json") << spec;
  const CommandOutcome typo = Cli("run irb1600 --spec " + Out("typo.json") + " --watch");
  EXPECT_EQ(typo.exit_code, 1) << typo.output;
  EXPECT_THAT(typo.output, HasSubstr("mbstream run: warning: pd_servo.kp = 1.23457e+29 on joint "
                                     "3 'joint3'"));
  EXPECT_THAT(typo.output, HasSubstr("mbstream run: warning: max_cpu_s = 1000 s exceeds this "
                                     "server's cap of 30 s"));
  EXPECT_THAT(typo.output, HasSubstr("run TOO_MUCH_WORK: budget exhausted: " + steps +
                                     " internal steps (max_internal_steps = " + steps + ")"));
  EXPECT_THAT(typo.output, HasSubstr("likely cause: pd_servo.kp = 1.23457e+29"));
  EXPECT_EQ(LastLine(typo.output), "trust: n/a");

  const std::string coarse =
      "run irb1600 --spec models/irb1600/passive-swing.json --method euler --step 0.01 --out ";
  const CommandOutcome untrusted = Cli(coarse + Out("untrusted"));
  EXPECT_EQ(untrusted.exit_code, 4) << untrusted.output;
  EXPECT_THAT(untrusted.output, HasSubstr("FINISHED"));
  EXPECT_EQ(LastLine(untrusted.output).rfind("trust: low (energy balance error ", 0), 0u)
      << untrusted.output;
  EXPECT_THAT(ReadFile(dir_ / "untrusted" / "stats.json"), HasSubstr("\"trust\": \"low\""));
  EXPECT_EQ(Cli(coarse + Out("accepted") + " --accept-untrusted").exit_code, 0);
}

// A missed accuracy target on the server is printed by `mbstream run --watch` as by
// `simulate` (before the trust line) and exits 4, or 0 with --accept-untrusted (issue 36.7).
TEST_F(ServerCliTest, MissedTargetIsPrintedAndExitsFour) {
  StartServer();
  const std::string run =
      "run irb1600 --spec models/irb1600/seed-servo.json --duration 0.5 --target-tcp 1e-12 "
      "--watch";
  const CommandOutcome missed = Cli(run);
  EXPECT_EQ(missed.exit_code, 4) << missed.output;
  EXPECT_THAT(missed.output, HasSubstr("FINISHED"));
  EXPECT_THAT(missed.output, HasSubstr("\ntarget: missed ("));
  EXPECT_EQ(LastLine(missed.output).rfind("trust: ", 0), 0u) << missed.output;
  EXPECT_EQ(Cli(run + " --accept-untrusted").exit_code, 0);
}

TEST_F(ServerCliTest, ErrorsAreNamedWithExitCodes) {
  StartServer();
  CommandOutcome outcome = Cli("run nosuch");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_THAT(outcome.output, HasSubstr("no model 'nosuch'"));
  outcome = Cli("run irb1600 --duration -1");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_THAT(outcome.output, HasSubstr("duration_s"));
  outcome = Cli("result r-nosuch --out " + Out("x"));
  EXPECT_EQ(outcome.exit_code, 2);
  outcome = RunCommand(std::string(MBSTREAM_CLI) + " --server unix:" + Out("nosocket") + " models");
  EXPECT_EQ(outcome.exit_code, 3);
  EXPECT_THAT(outcome.output, HasSubstr("is mbstream-server running"));
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// A sweep of servo gains as one request: a row per point in DIR/sweep.csv (grid order, the
// swept values as columns, then the summary), started in slices of a small window; a stiffer
// servo tracks better; kept frames go under runs/; a bad path is named before any run.
TEST_F(ServerCliTest, ASweepOfServoGainsWritesOneRowPerPoint) {
  StartServer();
  const std::string base = "sweep irb1600 --spec models/irb1600/seed-servo.json --duration 0.5 ";
  CommandOutcome sweep = Cli(base +
                             "--grid 'drives[1].pd_servo.kp=100,400,1600' "
                             "--grid rtol=1e-6:1e-8:2:log --window 2 --out " +
                             Out("sweep"));
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  EXPECT_THAT(sweep.output, HasSubstr("6 of 6 runs finished"));
  const std::vector<std::string> rows = Lines(ReadFile(dir_ / "sweep" / "sweep.csv"));
  ASSERT_EQ(rows.size(), 7u) << ReadFile(dir_ / "sweep" / "sweep.csv");
  EXPECT_EQ(rows[0].rfind("run_id,drives[1].pd_servo.kp,rtol,state,trust,", 0), 0u) << rows[0];
  EXPECT_THAT(rows[0], HasSubstr(",tracking_error_max:joint2,effort_peak:joint2,"));
  const auto cells = [](const std::string& row) {
    std::vector<std::string> out;
    std::istringstream in(row);
    for (std::string cell; std::getline(in, cell, ',');) out.push_back(cell);
    return out;
  };
  const std::vector<std::string> header = cells(rows[0]);
  const size_t tracking = static_cast<size_t>(
      std::find(header.begin(), header.end(), "tracking_error_max:joint2") - header.begin());
  ASSERT_LT(tracking, header.size());
  std::vector<double> error_by_kp;
  for (size_t r = 1; r < rows.size(); ++r) {
    const std::vector<std::string> row = cells(rows[r]);
    EXPECT_EQ(row[0].substr(0, 2), "r-");
    EXPECT_EQ(row[1],
              std::vector<std::string>({"100", "100", "400", "400", "1600", "1600"})[r - 1]);
    EXPECT_EQ(row[3], "FINISHED") << rows[r];
    if (r % 2 == 1) error_by_kp.push_back(std::stod(row[tracking]));
  }
  ASSERT_EQ(error_by_kp.size(), 3u);
  EXPECT_GT(error_by_kp[0], error_by_kp[1]);
  EXPECT_GT(error_by_kp[1], error_by_kp[2]);
  EXPECT_FALSE(fs::exists(dir_ / "sweep" / "runs")) << "a sweep keeps the summary by default";

  sweep = Cli(base + "--grid 'drives[0].pd_servo.kd=20,40' --keep every:5 --out " + Out("kept"));
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  int run_dirs = 0;
  for (const fs::directory_entry& run : fs::directory_iterator(dir_ / "kept" / "runs")) {
    ++run_dirs;
    EXPECT_EQ(Lines(ReadFile(run.path() / "joints.csv")).size(), 1u + 3u);  // 0, 5, 10 of 11
  }
  EXPECT_EQ(run_dirs, 2);

  sweep = Cli(base + "--grid 'drives[joint=joint2].pd_servo.kp=1' --out " + Out("bad"));
  EXPECT_EQ(sweep.exit_code, 2);
  EXPECT_THAT(sweep.output, HasSubstr("no element of the base spec's drives has joint = joint2"));
  sweep = Cli(base + "--grid rtol=-1,1e-6 --out " + Out("bad"));
  EXPECT_EQ(sweep.exit_code, 2);
  EXPECT_THAT(sweep.output, HasSubstr("rtol"));
  EXPECT_THAT(Cli("runs").output, Not(HasSubstr("FAILED")));
}

// A sweep's progress and its cancellation by id, from any client: --status prints what the
// server counts, --cancel marks it cancelled (its runs had ended: none is changed).
TEST_F(ServerCliTest, ASweepIsFollowedAndCancelledByItsId) {
  StartServer();
  const CommandOutcome sweep =
      Cli("sweep irb1600 --spec models/irb1600/seed-servo.json --duration 0.2 "
          "--grid 'drives[1].pd_servo.kp=100,400,1600' --out " +
          Out("sweep"));
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  EXPECT_THAT(sweep.output, HasSubstr("3/3 runs ended (FINISHED 3)"));
  const std::string id = SweepIdOf(sweep.output);
  ASSERT_FALSE(id.empty()) << sweep.output;

  CommandOutcome status = Cli("sweep --status " + id);
  ASSERT_EQ(status.exit_code, 0) << status.output;
  EXPECT_THAT(status.output, HasSubstr("sweep " + id + ": 3/3 runs ended (FINISHED 3)"));
  EXPECT_THAT(status.output, Not(HasSubstr("cancelled")));
  const CommandOutcome cancel = Cli("sweep --cancel " + id);
  ASSERT_EQ(cancel.exit_code, 0) << cancel.output;
  EXPECT_THAT(cancel.output, HasSubstr("(FINISHED 3) - cancelled"));
  status = Cli("sweep --status s-nosuch");
  EXPECT_NE(status.exit_code, 0);
  EXPECT_THAT(status.output, HasSubstr("s-nosuch"));
  EXPECT_EQ(Cli("sweep irb1600").exit_code, 2);  // no --out
}

// `mbstream cancel --sweep ID` is `mbstream sweep --cancel ID` under the command that cancels
// runs; a run id and --sweep together, or neither, are refused.
TEST_F(ServerCliTest, TheCancelCommandCancelsASweepByItsId) {
  StartServer();
  const CommandOutcome sweep =
      Cli("sweep irb1600 --spec models/irb1600/seed-servo.json --duration 0.1 "
          "--grid 'drives[1].pd_servo.kp=100,400' --out " +
          Out("sweep"));
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  const std::string id = SweepIdOf(sweep.output);
  ASSERT_FALSE(id.empty()) << sweep.output;

  const CommandOutcome cancel = Cli("cancel --sweep " + id);
  ASSERT_EQ(cancel.exit_code, 0) << cancel.output;
  EXPECT_THAT(cancel.output,
              HasSubstr("sweep " + id + ": 2/2 runs ended (FINISHED 2) - cancelled"));
  EXPECT_THAT(Cli("sweep --status " + id).output, HasSubstr("- cancelled"));
  const CommandOutcome unknown = Cli("cancel --sweep s-nosuch");
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_THAT(unknown.output, HasSubstr("mbstream cancel"));
  EXPECT_THAT(unknown.output, HasSubstr("s-nosuch"));
  EXPECT_EQ(Cli("cancel").exit_code, 2);
  EXPECT_NE(Cli("cancel r-1 --sweep " + id).exit_code, 0);
}

}  // namespace
}  // namespace mbstream::testing
