// A server killed with SIGKILL mid-run (issue 36 item 5): restarted on the same data
// directory, the run is INTERRUPTED with the frames it had stored (a chunk at least every
// --frame-flush-s, 1 s by default, not only every 4,096 frames), its row counts them, and
// `mbstream result` writes them: the same bytes as the first rows of the same run unpaced.
#include <gmock/gmock.h>
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <filesystem>
#include <random>
#include <sstream>
#include <thread>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "tests/common/csv_rows.h"
#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// seed-servo (joint dynamics: torques and energies too): 401 frames, one per 0.05 s.
constexpr const char* kSpec = "--spec models/irb1600/seed-servo.json";
constexpr double kRealtime = 2.0;
constexpr double kOutputInterval = 0.05;

std::unique_ptr<v1::Simulation::Stub> Connect(const std::string& address) {
  return v1::Simulation::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
}

v1::RunInfo GetRun(v1::Simulation::Stub& stub, const std::string& run_id) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
  v1::GetRunRequest request;
  request.set_run_id(run_id);
  v1::RunInfo info;
  const grpc::Status status = stub.GetRun(&context, request, &info);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return info;
}

// The first `count` lines of a text.
std::string FirstLines(const std::string& text, std::size_t count) {
  std::size_t end = 0;
  for (std::size_t i = 0; i < count && end != std::string::npos; ++i) {
    end = text.find('\n', end);
    if (end != std::string::npos) ++end;
  }
  return end == std::string::npos ? text : text.substr(0, end);
}

TEST(CrashFramesE2eTest, AKilledServersRunKeepsTheFramesItStoredAfterARestart) {
  const fs::path dir = fs::temp_directory_path() /
                       ("mbstream-crash-frames-" + std::to_string(std::random_device()()));
  fs::create_directories(dir);
  const std::string data = (dir / "data").string();
  std::string run_id;
  {
    ServerProcess server(MBSTREAM_SERVER, data);
    const CommandOutcome started =
        RunCommand(std::string(MBSTREAM_CLI) + " --server " + server.address() + " run irb1600 " +
                   kSpec + " --realtime " + std::to_string(kRealtime));
    ASSERT_EQ(started.exit_code, 0) << started.output;
    run_id = started.output.substr(0, started.output.find('\n'));

    // Frame k goes out no earlier than t_k / realtime after the run's start, and each frame
    // is given to the store's spool before it is published: once frame 40 (t = 2 s, 1 s of
    // wall time at 2x) is published, a chunk due after 1 s has been stored.
    const int64_t due_frames = static_cast<int64_t>(1.0 * kRealtime / kOutputInterval) + 1;
    auto stub = Connect(server.address());
    v1::RunInfo live;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    do {
      live = GetRun(*stub, run_id);
      const bool ended = live.state() != v1::QUEUED && live.state() != v1::RUNNING;
      if (live.frames() >= due_frames || ended) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));  // the next poll
    } while (std::chrono::steady_clock::now() < give_up);
    ASSERT_EQ(live.state(), v1::RUNNING) << live.message();
    ASSERT_GE(live.frames(), due_frames);
    ASSERT_LT(live.frames(), live.expected_frames());  // mid-run: 1 s of its 10 s
    std::cout << "killed at " << live.frames() << " frames published, t = " << live.t_s() << " s"
              << std::endl;
    server.Kill();
  }

  const fs::path killed = dir / "killed";
  v1::RunInfo after;
  {
    ServerProcess server(MBSTREAM_SERVER, data);
    auto stub = Connect(server.address());
    after = GetRun(*stub, run_id);
    const CommandOutcome result =
        RunCommand(std::string(MBSTREAM_CLI) + " --server " + server.address() + " result " +
                   run_id + " --out " + killed.string());
    EXPECT_EQ(result.exit_code, 1) << result.output;  // not FINISHED
    EXPECT_THAT(result.output,
                HasSubstr("INTERRUPTED: " + std::to_string(after.frames()) + " frames"));
    const CommandOutcome reference =
        RunCommand(std::string(MBSTREAM_CLI) + " --server " + server.address() + " run irb1600 " +
                   kSpec + " --realtime 0 --watch --out " + (dir / "reference").string());
    ASSERT_EQ(reference.exit_code, 0) << reference.output;
  }
  std::cout << "after the restart: " << after.frames() << " frames kept, t = " << after.t_s()
            << " s" << std::endl;
  EXPECT_EQ(after.state(), v1::INTERRUPTED);
  EXPECT_THAT(after.message(),
              HasSubstr("the " + std::to_string(after.frames()) + " frames stored up to t = "));
  ASSERT_GT(after.frames(), 0);
  ASSERT_LT(after.frames(), after.expected_frames());
  EXPECT_DOUBLE_EQ(after.t_s(), kOutputInterval * static_cast<double>(after.frames() - 1));
  EXPECT_EQ(after.stats().t_reached_s(), after.t_s());
  EXPECT_TRUE(after.has_torques());
  EXPECT_TRUE(after.has_energy());

  // The kept frames, as `mbstream result` writes them: the reference run's first rows.
  for (const char* file :
       {"joints.csv", "velocities.csv", "tcp.csv", "torques.csv", "energy.csv"}) {
    const std::string kept = ReadTextFile((killed / file).string());
    const std::string whole = ReadTextFile((dir / "reference" / file).string());
    EXPECT_EQ(ReadCsv(killed / file).size(), static_cast<std::size_t>(after.frames())) << file;
    EXPECT_EQ(kept, FirstLines(whole, static_cast<std::size_t>(after.frames()) + 1)) << file;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mbstream::testing
