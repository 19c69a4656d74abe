// `mbstream simulate --mcap` read back by an independent reader: @mcap/core (node,
// reader/read_mcap.js: schemas, channels, chunk indexes, every CRC) and a CDR decode of every
// JointState compared bit for bit with the run's CSV files; and a run of a million frames
// whose export's memory stays that of a chunk.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <string>
#include "tests/common/sanitized_build.h"

namespace {

namespace fs = std::filesystem;

// 2026-11-26T12:00:00.25Z, as --mcap-start gives it.
constexpr char kStart[] = "2026-11-26T12:00:00.25Z";
constexpr char kStartNs[] = "1795694400250000000";

std::string Read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

fs::path Scratch(const std::string& name) {
  return fs::temp_directory_path() / ("mbstream_mcap_" + name + "-" + std::to_string(getpid()));
}

struct Outcome {
  int exit_code = -1;
  long max_rss_kb = 0;  // the child's peak resident memory (getrusage's ru_maxrss)
};

// Runs `command` through the shell and waits for it with wait4, for its peak memory.
Outcome RunCommand(const std::string& command) {
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  Outcome outcome;
  if (wait4(pid, &status, 0, &usage) == pid && WIFEXITED(status)) {
    outcome.exit_code = WEXITSTATUS(status);
    outcome.max_rss_kb = usage.ru_maxrss;
  }
  return outcome;
}

// simulate MODEL --spec SPEC ARGS --out DIR --mcap DIR.mcap; the reader's JSON line (with
// `tcp_frame`, the reader checks /tf against tcp.csv).
nlohmann::json SimulateAndRead(const std::string& model, const std::string& spec,
                               const std::string& args, const std::string& name,
                               const std::string& tcp_frame = "") {
  const fs::path out = Scratch(name);
  fs::remove_all(out);
  const std::string mcap = out.string() + ".mcap";
  const std::string log = out.string() + ".log";
  const std::string simulate = std::string(MBSTREAM_CLI) + " simulate " + model + " --spec " +
                               spec + " " + args + " --mcap-start " + kStart + " --out " +
                               out.string() + " --mcap " + mcap + " > " + log + " 2>&1";
  const Outcome simulated = RunCommand(simulate);
  EXPECT_EQ(simulated.exit_code, 0) << Read(log);
  if (!fs::exists("tests/server/mcap/reader/node_modules/@mcap/core")) {
    ADD_FAILURE() << "tests/server/mcap/reader/node_modules has no @mcap/core: run "
                     "scripts/setup.sh (npm ci in tests/server/mcap/reader)";
    return {};
  }
  const std::string reader_out = out.string() + ".reader";
  const Outcome read =
      RunCommand("node tests/server/mcap/reader/read_mcap.js " + mcap + " " + out.string() + " " +
                 kStartNs + " " + model + " " + tcp_frame + " > " + reader_out + " 2>&1");
  const std::string text = Read(reader_out);
  EXPECT_EQ(read.exit_code, 0) << text;
  if (read.exit_code != 0) return {};
  fs::remove_all(out);
  fs::remove(mcap);
  fs::remove(log);
  fs::remove(reader_out);
  return nlohmann::json::parse(text);
}

TEST(McapExportTest, SeedRunZstdReadsBackBitForBit) {
  const nlohmann::json read =
      SimulateAndRead("models/irb1600/irb1600.urdf", "models/irb1600/seed-run.json",
                      "--duration 2 --mcap-compression zstd", "seed", "tcp");
  ASSERT_FALSE(read.is_null());
  // /tf and /tf_static composed from base_link to tcp: tcp.csv's position.
  EXPECT_LT(read["tcp_error_max_m"].get<double>(), 1e-12);
  // Foxglove's decoder, built from the three ros2msg schemas' text, read every message alike.
  EXPECT_EQ(read["foxglove_decoders"], 3);
  EXPECT_EQ(read["frames"], 41);
  EXPECT_EQ(read["compression"], "zstd");
  EXPECT_EQ(read["topics"]["/joint_states"]["schema"], "sensor_msgs/msg/JointState");
  EXPECT_EQ(read["topics"]["/joint_states"]["schemaEncoding"], "ros2msg");
  EXPECT_EQ(read["topics"]["/joint_states"]["messageEncoding"], "cdr");
  EXPECT_EQ(read["topics"]["/tf"]["schema"], "tf2_msgs/msg/TFMessage");
  EXPECT_EQ(read["topics"]["/robot_description"]["schema"], "std_msgs/msg/String");
  EXPECT_EQ(read["topics"]["/mbstream/stats"]["schemaEncoding"], "jsonschema");
  EXPECT_EQ(read["topics"]["/mbstream/probes"]["messageEncoding"], "json");
  EXPECT_EQ(read["messages"]["/joint_states"], 41);
  EXPECT_EQ(read["messages"]["/tf"], 41);
  EXPECT_EQ(read["messages"]["/robot_description"], 1);
  EXPECT_EQ(read["messages"]["/mbstream/stats"], 1);
  // 41 + 41 + robot_description + tf_static + stats.
  EXPECT_EQ(read["statistics_messages"], 85);
  EXPECT_EQ(read["tf"].size(), 6u);
  EXPECT_EQ(read["tf"][0], "base_link->link1");
  EXPECT_EQ(read["records"]["DataEnd"], 1);
}

TEST(McapExportTest, PassiveSwingLz4ReadsBackBitForBit) {
  const nlohmann::json read =
      SimulateAndRead("models/irb1600/irb1600.urdf", "models/irb1600/passive-swing.json",
                      "--duration 1 --mcap-compression lz4", "swing", "tcp");
  ASSERT_FALSE(read.is_null());
  EXPECT_LT(read["tcp_error_max_m"].get<double>(), 1e-12);
  EXPECT_EQ(read["compression"], "lz4");
  EXPECT_GT(read["frames"].get<int>(), 10);
}

TEST(McapExportTest, DrivenFourBarUncompressedNamesItsCutJoint) {
  const nlohmann::json read =
      SimulateAndRead("models/linkages/four_bar.sdf", "models/linkages/four_bar-driven.json",
                      "--mcap-compression none", "four_bar");
  ASSERT_FALSE(read.is_null());
  EXPECT_EQ(read["compression"], "");
  EXPECT_TRUE(read["has_effort"].get<bool>());
  // The JointState names are joints.csv's columns: the cut joint last.
  EXPECT_EQ(read["names"],
            nlohmann::json::array({"crank_joint", "rocker_joint", "coupler_joint", "loop_joint"}));
}

// A world of a robot and three free boxes (docs/worlds.md): /joint_states holds the robot's
// joints only; each box's pose is its /tf transform, equal to its seven joints.csv columns.
TEST(McapExportTest, WorldsFreeBodiesAreTheirTfPoses) {
  const nlohmann::json read = SimulateAndRead("models/worlds/irb1600_table/world.sdf",
                                              "models/worlds/irb1600_table/boxes-fall.json",
                                              "--mcap-compression zstd", "world");
  ASSERT_FALSE(read.is_null());
  EXPECT_EQ(read["names"].size(), 6u);
  EXPECT_EQ(read["names"][0], "irb1600::joint1");
  EXPECT_EQ(read["free_bodies"],
            nlohmann::json::array({"box_a::link", "box_b::link", "box_c::link"}));
  EXPECT_LT(read["free_pose_error_max"].get<double>(), 1e-12);
  EXPECT_GT(read["frames"].get<int>(), 5);
}

// An arm carrying a bob on a ball joint (tests/data/ball_arm.sdf): /joint_states holds the
// revolute joint only; the bob's /tf transform (its quaternion's rotation after the joint
// frame) puts tool0, fixed to the bob off the joint centre, where tcp.csv has it.
TEST(McapExportTest, ABallJointsChildIsItsTfPose) {
  const nlohmann::json read = SimulateAndRead(
      "tests/data/ball_arm.sdf", "tests/data/ball_arm-swing.json", "", "ball", "tool0");
  ASSERT_FALSE(read.is_null());
  EXPECT_EQ(read["names"], nlohmann::json::array({"shoulder"}));
  EXPECT_LT(read["tcp_error_max_m"].get<double>(), 1e-12);
  EXPECT_GT(read["frames"].get<int>(), 50);
}

// A million frames of the single pendulum, with and without --mcap: the export's memory is its
// chunk (1 MiB of records, its compressed copy, zstd's context), not the run's 47 MB file.
// docs/performance.md, "MCAP export", quotes these figures.
TEST(McapExportTest, MillionFramesExportInTheMemoryOfAChunk) {
  if (mbstream::testing::kSanitizedBuild) {
    GTEST_SKIP() << "under a sanitizer the peak RSS measures its quarantine of freed memory "
                    "(+222 MB under ASan), not the export; the Release build checks the bound";
  }
  const fs::path out = Scratch("million");
  const std::string simulate = std::string(MBSTREAM_CLI) +
                               " simulate models/pendulum/single_pendulum.urdf --duration 1000 "
                               "--output-interval 0.001 --max-duration 1000 "
                               "--max-output-frames 2000000 --out " +
                               out.string();
  fs::remove_all(out);
  const Outcome plain = RunCommand(simulate + " > /dev/null 2>&1");
  ASSERT_EQ(plain.exit_code, 0);
  fs::remove_all(out);
  const std::string mcap = out.string() + ".mcap";
  const Outcome exported = RunCommand(simulate + " --mcap " + mcap + " > /dev/null 2>&1");
  ASSERT_EQ(exported.exit_code, 0);
  const auto mcap_bytes = fs::file_size(mcap);
  fs::remove_all(out);
  fs::remove(mcap);
  const long extra_kb = exported.max_rss_kb - plain.max_rss_kb;
  std::cout << "1000001 frames: peak RSS " << plain.max_rss_kb << " KB without --mcap, "
            << exported.max_rss_kb << " KB with it (+" << extra_kb << " KB); MCAP file "
            << mcap_bytes << " bytes\n";
  EXPECT_GT(mcap_bytes, 20u << 20);  // the run really is large
  EXPECT_LT(extra_kb, 12 * 1024);
}

TEST(McapExportTest, BadStartTimeIsNamedBeforeTheRun) {
  const fs::path out = Scratch("bad_start");
  const std::string log = out.string() + ".log";
  const Outcome outcome =
      RunCommand(std::string(MBSTREAM_CLI) +
                 " simulate models/pendulum/single_pendulum.urdf --duration 0.1 "
                 "--mcap-start yesterday --out " +
                 out.string() + " --mcap " + out.string() + ".mcap > " + log + " 2>&1");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(Read(log).find("--mcap-start \"yesterday\": give a UTC time as "
                           "2026-11-26T12:00:00Z"),
            std::string::npos)
      << Read(log);
  EXPECT_FALSE(fs::exists(out.string() + ".mcap"));
  fs::remove_all(out);
  fs::remove(log);
}

}  // namespace
