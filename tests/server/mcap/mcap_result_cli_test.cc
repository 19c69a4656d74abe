// `mbstream result RUN --mcap FILE` against a live server: the stored run (its frames, probe
// reports and stats) as MCAP, the links' poses from the model the server sends back, read by
// @mcap/core and compared bit for bit with the same run's results files.
#include <gmock/gmock.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/common/cli_server_test.h"
#include "tests/common/sanitized_build.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class McapResultCliTest : public CliServerTest {
 protected:
  void SetUp() override {
    CliServerTest::SetUp();
    StartServer();
  }
};

// A field of /proc/PID/status in KB ("VmRSS", "VmHWM"); -1 when missing.
long StatusKb(pid_t pid, const std::string& field) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind(field + ":", 0) == 0) return std::stol(line.substr(field.size() + 1));
  }
  return -1;
}

// The peak RSS (KB) /usr/bin/time printed as "peak_kb N"; -1 when missing.
long PeakKb(const std::string& output) {
  const size_t at = output.rfind("peak_kb ");
  return at == std::string::npos ? -1 : std::stol(output.substr(at + 8));
}

TEST_F(McapResultCliTest, StoredServoRunExportsWithEffortsBitForBit) {
  ASSERT_EQ(Cli("submit models/irb1600").exit_code, 0);
  const CommandOutcome run =
      Cli("run irb1600 --spec models/irb1600/seed-servo.json --duration 2 --watch --out " +
          Out("results"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string run_id = run.output.substr(0, run.output.find('\n'));

  const CommandOutcome result = Cli("result " + run_id + " --mcap " + Out("run.mcap") +
                                    " --mcap-compression lz4 --mcap-start 1795694400.25");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_THAT(result.output, HasSubstr("MCAP in " + Out("run.mcap")));
  EXPECT_FALSE(fs::exists(Out("run.mcap") + ".tmp"));

  const CommandOutcome read =
      RunCommand("node tests/server/mcap/reader/read_mcap.js " + Out("run.mcap") + " " +
                 Out("results") + " 1795694400250000000 models/irb1600/irb1600.urdf tcp");
  ASSERT_EQ(read.exit_code, 0) << read.output;
  const nlohmann::json summary = nlohmann::json::parse(read.output);
  EXPECT_EQ(summary["frames"], 41);
  EXPECT_EQ(summary["compression"], "lz4");
  EXPECT_TRUE(summary["has_effort"].get<bool>());
  EXPECT_EQ(summary["tf"].size(), 6u);
  EXPECT_LT(summary["tcp_error_max_m"].get<double>(), 1e-12);
}

// A stored run of a world with free bodies (docs/worlds.md): its /tf holds each box's pose,
// equal to its seven joints.csv columns; /joint_states the robot's joints.
TEST_F(McapResultCliTest, StoredWorldRunExportsItsFreeBodiesAsTfPoses) {
  ASSERT_EQ(Cli("submit models/worlds/irb1600_table --name irb1600_table").exit_code, 0);
  const CommandOutcome run =
      Cli("run irb1600_table --spec models/worlds/irb1600_table/boxes-fall.json --watch --out " +
          Out("world"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string run_id = run.output.substr(0, run.output.find('\n'));
  const CommandOutcome result =
      Cli("result " + run_id + " --mcap " + Out("world.mcap") + " --mcap-start 1795694400.25");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  // The model the server sends back is the world with its includes written in: the reader
  // compares /robot_description with that text (`mbstream model ... --save`'s file).
  const CommandOutcome read =
      RunCommand("node tests/server/mcap/reader/read_mcap.js " + Out("world.mcap") + " " +
                 Out("world") + " 1795694400250000000 -");
  ASSERT_EQ(read.exit_code, 0) << read.output;
  const nlohmann::json summary = nlohmann::json::parse(read.output);
  EXPECT_EQ(summary["frames"], 21);
  EXPECT_EQ(summary["names"].size(), 6u);
  EXPECT_EQ(summary["free_bodies"].size(), 3u);
  EXPECT_LT(summary["free_pose_error_max"].get<double>(), 1e-12);
}

// A stored run of a million frames exported: the server reads it one stored chunk at a time into
// the writer and sends each MiB of the file as it is written; the CLI appends it to the file.
// Neither holds the run. docs/performance.md, "MCAP export", quotes these figures.
TEST(McapResultMillionTest, MillionFramesExportThroughTheServerInTheMemoryOfAChunk) {
  if (kSanitizedBuild)
    GTEST_SKIP() << "a sanitizer's quarantine, not the export, would be measured";
  if (!fs::exists("/usr/bin/time")) GTEST_SKIP() << "no /usr/bin/time (Debian: time)";
  const fs::path dir = fs::temp_directory_path() /
                       ("mbstream-mcap-million-" + std::to_string(std::random_device()()));
  fs::create_directories(dir);
  ServerProcess server(MBSTREAM_SERVER, (dir / "data").string(),
                       {"--max-duration", "1000", "--max-output-frames", "2000000"});
  const std::string cli = std::string(MBSTREAM_CLI) + " --server " + server.address() + " ";
  ASSERT_EQ(RunCommand(cli + "submit models/pendulum/single_pendulum.urdf").exit_code, 0);
  const CommandOutcome run =
      RunCommand(cli + "run single_pendulum --duration 1000 --output-interval 0.001 --watch");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string run_id = run.output.substr(0, run.output.find('\n'));

  const long server_before_kb = StatusKb(server.pid(), "VmRSS");
  std::ofstream(("/proc/" + std::to_string(server.pid()) + "/clear_refs").c_str()) << "5";
  const std::string mcap = (dir / "million.mcap").string();
  const CommandOutcome exported = RunCommand("/usr/bin/time -f 'peak_kb %M' " + cli + "result " +
                                             run_id + " --mcap " + mcap + " 2>&1");
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  const long server_peak_kb = StatusKb(server.pid(), "VmHWM");
  const long client_peak_kb = PeakKb(exported.output);
  const auto mcap_bytes = fs::file_size(mcap);
  std::cout << "1000001 frames: `result --mcap` peak RSS " << client_peak_kb << " KB; server "
            << server_before_kb << " KB before, peak " << server_peak_kb
            << " KB during the export; MCAP file " << mcap_bytes << " bytes\n";
  EXPECT_GT(mcap_bytes, 20u << 20);  // the run really is large
  EXPECT_GT(client_peak_kb, 0) << exported.output;
  EXPECT_LT(client_peak_kb, 40 * 1024);  // the CLI's own size and a message of 1 MiB
  if (server_before_kb > 0 && server_peak_kb > 0) {
    EXPECT_LT(server_peak_kb - server_before_kb, 24 * 1024);  // a stored chunk, an MCAP chunk
  }
  server.Stop();
  fs::remove_all(dir);
}

TEST_F(McapResultCliTest, NothingToWriteIsSaidBeforeAnyCall) {
  const CommandOutcome result = Cli("result r-none");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output,
              HasSubstr("nothing to write: give --out DIR (the results files), --mcap FILE, or "
                        "both"));
  const CommandOutcome bad = Cli("result r-none --mcap x.mcap --mcap-compression gzip");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.output, HasSubstr("unknown MCAP compression \"gzip\": use zstd, lz4 or none"));
}

}  // namespace
}  // namespace mbstream::testing
