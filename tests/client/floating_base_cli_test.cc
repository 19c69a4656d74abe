// `--floating-base` as a user runs it (issue 43, docs/worlds.md): a published humanoid's URDF
// (Atlas v3, Debian's dart-doc) whose root link is not fixed, through `mbstream simulate
// --floating-base` and through a live server (`mbstream submit --floating-base`, then `run`).
// Its root gets a free joint named after the root link (pelvis.x ... pelvis.qz in joints.csv),
// and, released at rest with contact off (nothing touches), the whole robot falls: the
// pelvis's z follows -g t^2 / 2, its x, y and quaternion stay, and no joint moves.
#include <gmock/gmock.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/common/cli_server_test.h"
#include "tests/common/csv_rows.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr char kAtlas[] = "/usr/share/doc/dart/data/sdf/atlas/atlas_v3_no_head.urdf";
constexpr double kG = 9.81;  // m/s^2, the spec's

std::vector<std::string> Header(const fs::path& csv) {
  std::vector<std::string> names;
  std::stringstream line(FirstLine(ReadFile(csv)));
  for (std::string name; std::getline(line, name, ',');) names.push_back(name);
  return names;
}

class FloatingBaseCliTest : public CliServerTest {
 protected:
  void SetUp() override {
    CliServerTest::SetUp();
    if (!fs::exists(kAtlas)) {
      if (std::getenv("MBSTREAM_CI")) FAIL() << kAtlas << " is missing: setup.sh installs dart-doc";
      GTEST_SKIP() << kAtlas << " is missing (Debian's dart-doc)";
    }
    std::ofstream(dir_ / "fall.json") << R"({"duration_s": 0.3, "output_interval_s": 0.02,
      "formulation": "joint", "method": "bdf", "rtol": 1e-10, "atol": 1e-12,
      "gravity": {"z": -9.81}, "contact": {"enabled": false}})";
  }
  std::string Spec() const { return (dir_ / "fall.json").string(); }

  // joints.csv of a fall: the free joint's 7 columns first, then Atlas's 27 revolute joints.
  void ExpectAFreeFall(const std::string& out) {
    const std::vector<std::string> names = Header(dir_ / out / "joints.csv");
    ASSERT_EQ(names.size(), 1u + 7 + 27) << FirstLine(ReadFile(dir_ / out / "joints.csv"));
    const std::vector<std::string> free(names.begin() + 1, names.begin() + 8);
    EXPECT_EQ(free, (std::vector<std::string>{"pelvis.x", "pelvis.y", "pelvis.z", "pelvis.qw",
                                              "pelvis.qx", "pelvis.qy", "pelvis.qz"}));
    EXPECT_EQ(Header(dir_ / out / "velocities.csv").size(), 1u + 6 + 27);
    const std::vector<std::vector<std::string>> rows = ReadCsv(dir_ / out / "joints.csv");
    ASSERT_EQ(rows.size(), 16u);
    double off_fall = 0, off_rest = 0;
    for (const auto& row : rows) {
      const double t = std::stod(row[0]);
      const auto at = [&](size_t k) { return std::stod(row.at(k)); };
      off_fall = std::max(
          {off_fall, std::abs(at(1)), std::abs(at(2)), std::abs(at(3) + 0.5 * kG * t * t)});
      off_rest = std::max(
          {off_rest, std::abs(at(4) - 1.0), std::abs(at(5)), std::abs(at(6)), std::abs(at(7))});
      for (size_t k = 8; k < row.size(); ++k) off_rest = std::max(off_rest, std::abs(at(k)));
    }
    std::cout << out << ": pelvis off -g t^2/2 by at most " << off_fall
              << " m; quaternion and joints off their start by " << off_rest << "\n";
    EXPECT_NEAR(std::stod(rows.back()[3]), -0.5 * kG * 0.3 * 0.3, 1e-8);  // it fell 0.44 m
    EXPECT_LT(off_fall, 1e-8) << out;
    EXPECT_LT(off_rest, 1e-8) << out;
  }
};

TEST_F(FloatingBaseCliTest, SimulateFreesTheRootAndTheRobotFalls) {
  const CommandOutcome run =
      RunCommand(std::string(MBSTREAM_CLI) + " simulate " + kAtlas + " --floating-base --spec " +
                 Spec() + " --out " + Out("local"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ExpectAFreeFall("local");
  // Without the flag the root is the world's: no free joint, the robot hangs where it is.
  const CommandOutcome fixed =
      RunCommand(std::string(MBSTREAM_CLI) + " simulate " + kAtlas + " --spec " + Spec() +
                 " --duration 0.02 --out " + Out("fixed"));
  ASSERT_EQ(fixed.exit_code, 0) << fixed.output;
  EXPECT_EQ(Header(dir_ / "fixed" / "joints.csv").size(), 1u + 27);
}

TEST_F(FloatingBaseCliTest, ASubmittedFloatingBaseRunsOnAServer) {
  StartServer();
  const CommandOutcome submit =
      Cli(std::string("submit ") + kAtlas + " --floating-base --name atlas");
  ASSERT_EQ(submit.exit_code, 0) << submit.output;
  const CommandOutcome run = Cli("run atlas --spec " + Spec() + " --watch --out " + Out("served"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("FINISHED"));
  ExpectAFreeFall("served");
  const CommandOutcome local =
      RunCommand(std::string(MBSTREAM_CLI) + " simulate " + kAtlas + " --floating-base --spec " +
                 Spec() + " --out " + Out("local"));
  ASSERT_EQ(local.exit_code, 0) << local.output;
  EXPECT_EQ(ReadFile(dir_ / "served" / "joints.csv"), ReadFile(dir_ / "local" / "joints.csv"));
}

}  // namespace
}  // namespace mbstream::testing
