// Real server + real offscreen viewer (Xvfb) + CLI: a replayed run gives the probes its live
// run gave, bit for bit; a replay from a frame answers from that frame on; a comparison's
// HUD distance is the distance between the two runs' tcp.csv.
#include <gmock/gmock.h>
#include <grpcpp/grpcpp.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

#include "mbstream/v1/viewer_service.grpc.pb.h"
#include "tests/common/cli_server_test.h"
#include "tests/common/csv_rows.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using Rows = std::vector<std::vector<std::string>>;

class ReplayE2eTest : public CliServerTest {
 protected:
  void SetUp() override {
    CliServerTest::SetUp();
    StartServer();
  }
  // Starts a --follow viewer in the background that exits after one run; waits until it
  // is subscribed.
  void StartFollower(const fs::path& log) {
    ASSERT_EQ(RunCommand("scripts/with-xvfb.sh " + std::string(MBSTREAM_VIEWER) + " --server " +
                         server_->address() + " --offscreen --size 320x240 --follow " +
                         "--exit-after-runs 1 > " + log.string() + " 2>&1 &")
                  .exit_code,
              0);
    ASSERT_TRUE(WaitForLineIn(log.string(), "subscribed to")) << ReadTextFile(log.string());
  }
  // Runs a viewer to its end; returns its output.
  CommandOutcome Viewer(const std::string& args) {
    return RunCommand("scripts/with-xvfb.sh " + std::string(MBSTREAM_VIEWER) + " --server " +
                      server_->address() + " --offscreen --size 320x240 " + args);
  }
  std::string RunId(const CommandOutcome& run) {
    return run.output.substr(0, run.output.find('\n'));
  }
  // The results of `run` (with the probes of `probe_set`, when given) in dir_/name.
  fs::path Result(const std::string& run, const std::string& name,
                  const std::string& probe_set = "") {
    const fs::path out = dir_ / name;
    const CommandOutcome result = Cli("result " + run + " --out " + out.string() +
                                      (probe_set.empty() ? "" : " --probe-set " + probe_set));
    EXPECT_EQ(result.exit_code, 0) << result.output;
    return out;
  }
  // The id of the run's only probe set (from `mbstream probe-sets`).
  std::string OnlyProbeSet(const std::string& run) {
    const CommandOutcome sets = Cli("probe-sets " + run);
    EXPECT_EQ(sets.exit_code, 0) << sets.output;
    std::stringstream lines(sets.output);
    std::string line, id;
    std::getline(lines, line);  // header
    int count = 0;
    while (std::getline(lines, line)) {
      id = line.substr(0, line.find(' '));
      ++count;
    }
    EXPECT_EQ(count, 1) << sets.output;
    return id;
  }
};

TEST_F(ReplayE2eTest, ReplayAnswersWithTheLiveRunsProbesBitForBit) {
  const fs::path log = dir_ / "live.log";
  ASSERT_NO_FATAL_FAILURE(StartFollower(log));
  const CommandOutcome run =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --realtime 10 --watch");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string run_id = RunId(run);
  ASSERT_TRUE(WaitForLineIn(log.string(), "viewer done")) << ReadTextFile(log.string());

  const CommandOutcome replay = Viewer("--run " + run_id + " --speed 0");
  ASSERT_EQ(replay.exit_code, 0) << replay.output;
  EXPECT_THAT(replay.output, HasSubstr("subscribed to"));
  EXPECT_THAT(replay.output, HasSubstr("401 frames, 401 probe reports"));
  const std::string set = OnlyProbeSet(run_id);
  EXPECT_THAT(replay.output, HasSubstr("probe set " + set));

  const Rows live = ReadCsv(Result(run_id, "live") / "probes.csv");
  const Rows replayed = ReadCsv(Result(run_id, "replay", set) / "probes.csv");
  ASSERT_EQ(live.size(), 401u);
  ASSERT_EQ(replayed.size(), live.size());
  for (size_t i = 0; i < live.size(); ++i) {
    for (int column : {0, 1, 2, 3, 4, 5}) {  // seq, t, name, x, y, z: the same text
      ASSERT_EQ(replayed[i][column], live[i][column]) << "row " << i << " column " << column;
    }
  }
  // The replay's joints are the live run's: the same frames (one results directory each).
  EXPECT_EQ(ReadTextFile((dir_ / "live" / "joints.csv").string()),
            ReadTextFile((dir_ / "replay" / "joints.csv").string()));
}

TEST_F(ReplayE2eTest, ReplayFromAFrameAnswersFromThatFrameOn) {
  const CommandOutcome run =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --realtime 0 "
          "--watch");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string run_id = RunId(run);
  const CommandOutcome replay = Viewer("--run " + run_id + " --speed 0 --from-frame 300");
  ASSERT_EQ(replay.exit_code, 0) << replay.output;
  const Rows probes = ReadCsv(Result(run_id, "seek", OnlyProbeSet(run_id)) / "probes.csv");
  const Rows tcp = ReadCsv(dir_ / "seek" / "tcp.csv");
  ASSERT_EQ(probes.size(), 101u);  // frames 300 .. 400
  EXPECT_EQ(probes.front()[0], "300");
  EXPECT_EQ(probes.front()[1], tcp.at(300)[0]);  // t = 15 s
  EXPECT_EQ(probes.back()[0], "400");

  const CommandOutcome beyond = Viewer("--run " + run_id + " --from-frame 401");
  EXPECT_EQ(beyond.exit_code, 1);
  EXPECT_THAT(beyond.output, HasSubstr("from_seq is 401 but run " + run_id + " has 401 frames"));
}

TEST_F(ReplayE2eTest, ComparisonHudDistanceIsTheDistanceBetweenTheTcpFiles) {
  const CommandOutcome bdf =
      Cli("run irb1600 --spec models/irb1600/seed-servo.json --duration 4 "
          "--realtime 0 --watch");
  ASSERT_EQ(bdf.exit_code, 0) << bdf.output;
  const CommandOutcome euler =
      Cli("run irb1600 --spec models/irb1600/seed-servo.json --duration 4 --realtime 0 "
          "--method euler --step 1e-4 --output-interval 0.01 --watch");
  ASSERT_EQ(euler.exit_code, 0) << euler.output;
  const std::string a = RunId(bdf), b = RunId(euler);
  const CommandOutcome viewer = Viewer("--run " + a + " --compare " + b + " --speed 0");
  ASSERT_EQ(viewer.exit_code, 0) << viewer.output;

  const Rows tcp_a = ReadCsv(Result(a, "a") / "tcp.csv");
  const Rows tcp_b = ReadCsv(Result(b, "b") / "tcp.csv");
  ASSERT_EQ(tcp_a.size(), 81u);
  ASSERT_EQ(tcp_b.size(), 401u);
  double max_distance = -1.0, max_t = 0.0;
  for (size_t k = 0; k < tcp_a.size(); ++k) {
    const auto& p = tcp_a[k];
    const auto& g = tcp_b.at(5 * k);  // the common grid: every 5th frame of the finer run
    ASSERT_NEAR(std::stod(p[0]), std::stod(g[0]), 1e-9);
    const double dx = std::stod(p[1]) - std::stod(g[1]), dy = std::stod(p[2]) - std::stod(g[2]),
                 dz = std::stod(p[3]) - std::stod(g[3]);
    const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (d > max_distance) {
      max_distance = d;
      max_t = std::stod(p[0]);
    }
  }
  EXPECT_GT(max_distance, 0.0);
  const std::string marker = "compare " + a + " with ghost " + b + ": ";
  const size_t at = viewer.output.find(marker);
  ASSERT_NE(at, std::string::npos) << viewer.output;
  std::stringstream line(viewer.output.substr(at + marker.size()));
  long long ghost_frames = 0;
  std::string word;
  line >> ghost_frames;
  EXPECT_EQ(ghost_frames, 81);
  while (line >> word && word != "TCP|") {
  }
  double hud_max = 0.0, hud_t = 0.0;
  line >> hud_max >> word >> word >> word >> word >> hud_t;  // "X m at t = T"
  EXPECT_EQ(hud_max, max_distance);                          // bit for bit
  EXPECT_EQ(hud_t, max_t);

  const CommandOutcome other = Cli("run single_pendulum --realtime 0 --watch");
  const CommandOutcome refused = Viewer("--run " + a + " --compare " + RunId(other));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_THAT(refused.output, HasSubstr("their models' joints differ"));
}

TEST_F(ReplayE2eTest, ReplayCommandStreamsAStoredRunToTheFollowingViewers) {
  const CommandOutcome run =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --realtime 0 "
          "--watch");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const fs::path log = dir_ / "follower.log";
  ASSERT_NO_FATAL_FAILURE(StartFollower(log));
  const CommandOutcome replay = Cli("replay " + RunId(run) + " --speed 20");
  ASSERT_EQ(replay.exit_code, 0) << replay.output;
  EXPECT_THAT(replay.output, HasSubstr("replaying 401 frames"));
  ASSERT_TRUE(WaitForLineIn(log.string(), "viewer done")) << ReadTextFile(log.string());
  EXPECT_THAT(ReadTextFile(log.string()),
              HasSubstr("last run " + RunId(run) + ": 401 frames, 401 probe reports"));
  EXPECT_EQ(Cli("replay r-nosuch").exit_code, 2);
}

// The viewer's control service drives a paused replay as its keys would: the pause holds
// (the probe set has the held frame and the stepped one, nothing between), a seek lands on
// its frame, and resume plays the rest.
TEST_F(ReplayE2eTest, ControlServiceStepsAndSeeksAPausedReplay) {
  const CommandOutcome run =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --realtime 0 "
          "--watch");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string run_id = RunId(run);
  const fs::path log = dir_ / "paused.log";
  ASSERT_EQ(RunCommand("scripts/with-xvfb.sh " + std::string(MBSTREAM_VIEWER) + " --server " +
                       server_->address() + " --offscreen --size 320x240 --run " + run_id +
                       " --paused --from-frame 100 --speed 0 --listen 127.0.0.1:0 > " +
                       log.string() + " 2>&1 &")
                .exit_code,
            0);
  const std::optional<std::string> address =
      WaitForLineIn(log.string(), "control service listening on ");
  ASSERT_TRUE(address) << ReadTextFile(log.string());
  auto viewer =
      v1::Viewer::NewStub(grpc::CreateChannel(*address, grpc::InsecureChannelCredentials()));
  // Waits (30 s at most) until the viewer shows frame `seq` of the replay.
  auto shows = [&](int64_t seq) {
    v1::ViewerStatus status;
    for (int i = 0; i < 3000; ++i) {
      grpc::ClientContext context;
      if (viewer->GetStatus(&context, v1::ViewerStatusRequest(), &status).ok() &&
          status.mode() == "replay" && status.seq() == seq) {
        return status;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ADD_FAILURE() << "the viewer never showed frame " << seq << "; it shows " << status.seq();
    return status;
  };
  auto control = [&](const std::function<void(v1::ReplayControl&)>& set) {
    grpc::ClientContext context;
    v1::ReplayControl request;
    set(request);
    v1::ViewerStatus status;
    const grpc::Status sent = viewer->Control(&context, request, &status);
    EXPECT_TRUE(sent.ok()) << sent.error_message();
  };
  EXPECT_TRUE(shows(100).paused());
  control([](v1::ReplayControl& c) { c.set_step(5); });
  EXPECT_TRUE(shows(105).paused());
  control([](v1::ReplayControl& c) { c.set_seek_seq(390); });
  EXPECT_TRUE(shows(390).paused());
  control([](v1::ReplayControl& c) { c.set_resume(true); });
  ASSERT_TRUE(WaitForLineIn(log.string(), "viewer done")) << ReadTextFile(log.string());

  const Rows probes = ReadCsv(Result(run_id, "controlled", OnlyProbeSet(run_id)) / "probes.csv");
  std::vector<std::string> seqs;
  for (const auto& row : probes) seqs.push_back(row[0]);
  EXPECT_EQ(seqs, (std::vector<std::string>{"100", "105", "390", "391", "392", "393", "394", "395",
                                            "396", "397", "398", "399", "400"}));
}

}  // namespace
}  // namespace mbstream::testing
