// A sweep belongs to the server (issue 42, item 1): a real mbstream-server and the CLI. The
// CLI interrupted (Ctrl-C) mid-sweep detaches and every point still finishes;
// `mbstream sweep --wait ID` picks the sweep up from another client and writes its whole
// table. The server killed (SIGKILL) mid-sweep and started again on its data goes on: the runs
// it was integrating are queued again (docs/cluster.md, "Sweeps"), the points it had not
// queued are queued by the new server, and the sweep completes. Waits are for events (a
// table's rows, a sweep's count through GetSweep); deadlines are failure guards only.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "tests/common/server_process.h"

extern char** environ;

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;

constexpr auto kGuard = std::chrono::seconds(120);  // a failure guard, far beyond the events

class SweepE2eTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mbstream-sweep-e2e-" + std::to_string(std::random_device()()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::unique_ptr<ServerProcess> StartServer() {
    return std::make_unique<ServerProcess>(
        MBSTREAM_SERVER, (dir_ / "data").string(),
        std::vector<std::string>{"--models", std::string(MBSTREAM_SOURCE_DIR) + "/models",
                                 "--workers", "2"});
  }
  static std::unique_ptr<v1::Simulation::Stub> Connect(const ServerProcess& server) {
    return v1::Simulation::NewStub(
        grpc::CreateChannel(server.address(), grpc::InsecureChannelCredentials()));
  }
  static v1::SweepProgress Progress(v1::Simulation::Stub& stub, const std::string& id) {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
    v1::GetSweepRequest request;
    request.set_sweep_id(id);
    v1::SweepProgress progress;
    const grpc::Status status = stub.GetSweep(&context, request, &progress);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return progress;
  }
  // Polls GetSweep until `done` holds (the server's count moving); the guard fails the test.
  static v1::SweepProgress AwaitSweep(v1::Simulation::Stub& stub, const std::string& id,
                                      const std::function<bool(const v1::SweepProgress&)>& done) {
    const auto guard = std::chrono::steady_clock::now() + kGuard;
    for (;;) {
      v1::SweepProgress progress = Progress(stub, id);
      if (done(progress) || std::chrono::steady_clock::now() > guard) return progress;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  static int CountIn(const v1::SweepProgress& progress, v1::RunState state) {
    for (const v1::SweepStateCount& entry : progress.states()) {
      if (entry.state() == state) return entry.runs();
    }
    return 0;
  }
  static std::vector<std::string> Lines(const fs::path& file) {
    std::ifstream in(file);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }

  fs::path dir_;
};

// `count` points of runs of `first` s, `first` + 0.05 s, ... paced at real time, at most
// `window` at once.
v1::StartSweepRequest PacedSweep(int count, double first, int window) {
  v1::StartSweepRequest request;
  request.set_model("single_pendulum");
  request.mutable_base()->set_output_interval_s(0.01);
  request.mutable_base()->set_realtime(1.0);
  request.mutable_base()->set_keep("all");  // pacing paces the frames kept
  v1::SweepAxis& axis = *request.add_grid();
  axis.set_path("duration_s");
  for (int k = 0; k < count; ++k) axis.add_values(std::to_string(first + 0.05 * k));
  request.set_window(window);
  return request;
}

TEST_F(SweepE2eTest, TheCliInterruptedMidSweepDetachesAndEveryPointStillFinishes) {
  auto server = StartServer();
  auto stub = Connect(*server);
  const fs::path out = dir_ / "out";
  const fs::path log = dir_ / "cli.log";
  // The CLI in a process of its own: 8 points of 0.3 to 0.65 s paced at real time, 2 at once.
  const fs::path spec = dir_ / "paced.json";
  // Pacing paces the frames kept: the runs keep theirs (the CLI writes them under runs/).
  std::ofstream(spec) << R"({"outputIntervalS": 0.01, "realtime": 1, "keep": "all"})";
  std::vector<std::string> args = {MBSTREAM_CLI,
                                   "--server",
                                   server->address(),
                                   "sweep",
                                   "single_pendulum",
                                   "--spec",
                                   spec.string(),
                                   "--grid",
                                   "duration_s=0.3:0.65:8",
                                   "--window",
                                   "2",
                                   "--out",
                                   out.string()};
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t cli = -1;
  ASSERT_EQ(posix_spawn(&cli, argv[0], &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);

  // Mid-sweep: its table has its first row (a run ended), most points not run yet.
  const auto guard = std::chrono::steady_clock::now() + kGuard;
  while (Lines(out / "sweep.csv").size() < 2 && std::chrono::steady_clock::now() < guard) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_GE(Lines(out / "sweep.csv").size(), 2u) << ReadTextFile(log.string());
  ASSERT_EQ(::kill(cli, SIGINT), 0);  // Ctrl-C
  int status = 0;
  ASSERT_EQ(::waitpid(cli, &status, 0), cli);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << status;
  const std::string said = ReadTextFile(log.string());
  EXPECT_NE(said.find("detached"), std::string::npos) << said;
  const size_t at = said.find("sweep s-");
  ASSERT_NE(at, std::string::npos) << said;
  const std::string id = said.substr(at + 6, said.find(':', at) - at - 6);

  EXPECT_LT(Progress(*stub, id).ended_runs(), 8) << "the CLI was stopped after the sweep ended";
  // The server goes on without its client: every point finishes.
  const v1::SweepProgress done = AwaitSweep(
      *stub, id, [](const v1::SweepProgress& p) { return p.ended_runs() == p.total_points(); });
  EXPECT_EQ(done.total_points(), 8);
  EXPECT_EQ(done.started_runs(), 8);
  EXPECT_EQ(CountIn(done, v1::FINISHED), 8);
  EXPECT_LE(Lines(out / "sweep.csv").size(), 8u);  // the CLI had not seen them all

  // Any client picks it up: its whole table.
  const CommandOutcome wait =
      RunCommand(std::string(MBSTREAM_CLI) + " --server " + server->address() + " sweep --wait " +
                 id + " --out " + (dir_ / "again").string());
  ASSERT_EQ(wait.exit_code, 0) << wait.output;
  EXPECT_NE(wait.output.find("8 of 8 runs finished"), std::string::npos) << wait.output;
  const std::vector<std::string> rows = Lines(dir_ / "again" / "sweep.csv");
  ASSERT_EQ(rows.size(), 9u);  // the header and a row per point, in point order
  EXPECT_NE(rows[1].find(",0.3,"), std::string::npos) << rows[1];
  EXPECT_NE(rows[8].find(",0.65,"), std::string::npos) << rows[8];
}

TEST_F(SweepE2eTest, AServerKilledMidSweepAndStartedAgainCompletesTheSweep) {
  auto server = StartServer();
  auto stub = Connect(*server);
  v1::StartSweepResponse started;
  {
    grpc::ClientContext context;
    const grpc::Status status = stub->StartSweep(&context, PacedSweep(8, 0.5, 3), &started);
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  const std::string id = started.sweep_id();
  // Mid-sweep: some runs ended, two running, points not queued yet.
  const v1::SweepProgress before = AwaitSweep(*stub, id, [](const v1::SweepProgress& p) {
    return p.ended_runs() >= 2 && CountIn(p, v1::RUNNING) == 2;
  });
  ASSERT_GE(before.ended_runs(), 2);
  ASSERT_LT(before.started_runs(), 8);
  server->Kill();  // SIGKILL: a crash

  server = StartServer();  // the same data
  stub = Connect(*server);
  const v1::SweepProgress done = AwaitSweep(
      *stub, id, [](const v1::SweepProgress& p) { return p.ended_runs() == p.total_points(); });
  EXPECT_EQ(done.total_points(), 8);
  EXPECT_EQ(done.started_runs(), 8);
  EXPECT_EQ(CountIn(done, v1::FINISHED), 8);  // the runs it was integrating ran again
  ASSERT_EQ(done.run_ids_size(), 8);
  EXPECT_EQ(std::set<std::string>(done.run_ids().begin(), done.run_ids().end()).size(), 8u);
  for (const std::string& run_id : done.run_ids()) {
    grpc::ClientContext context;
    v1::GetRunRequest request;
    request.set_run_id(run_id);
    v1::RunInfo info;
    ASSERT_TRUE(stub->GetRun(&context, request, &info).ok());
    EXPECT_EQ(info.state(), v1::FINISHED) << run_id << ": " << info.message();
  }
}

}  // namespace
}  // namespace mbstream::testing
