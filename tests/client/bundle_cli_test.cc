// Model bundles as a user submits them: `mbstream submit` and `mbstream simulate` on small
// robots written by the tests (--repair, description folders with package:// meshes),
// against a real mbstream-server.
#include <gmock/gmock.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

// One revolute joint; `arm_inertia` is the <inertia> element of the moving link.
std::string OneJointUrdf(const std::string& arm_inertia) {
  return R"(<robot name="odd">
  <link name="base"/>
  <link name="arm"><inertial><mass value="2"/>)" +
         arm_inertia + R"(</inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
)";
}

// 0.1 + 0.1 < 0.2001: the triangle inequality broken by 1e-4, as CAD exports do.
const char kBrokenInertia[] =
    R"(<inertia ixx="0.1" iyy="0.1" izz="0.2001" ixy="0" ixz="0" iyz="0"/>)";

class BundleCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device random;
    dir_ = fs::temp_directory_path() / ("mbstream-bundle-" + std::to_string(random()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    server_.reset();
    fs::remove_all(dir_);
  }
  void StartServer(const std::vector<std::string>& args = {}) {
    server_ = std::make_unique<ServerProcess>(MBSTREAM_SERVER, (dir_ / "data").string(), args);
  }
  CommandOutcome Cli(const std::string& args) {
    return RunCommand(std::string(MBSTREAM_CLI) + " --server " + server_->address() + " " + args);
  }
  CommandOutcome Local(const std::string& args) {
    return RunCommand(std::string(MBSTREAM_CLI) + " " + args);
  }
  // Writes `text` to dir_/relative (creating folders); returns the path.
  std::string Write(const std::string& relative, const std::string& text) {
    const fs::path path = dir_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
  }

  fs::path dir_;
  std::unique_ptr<ServerProcess> server_;
};

TEST_F(BundleCliTest, SubmitRepairFixesATriangleInequalityDefect) {
  StartServer();
  const std::string urdf = Write("odd.urdf", OneJointUrdf(kBrokenInertia));
  const CommandOutcome refused = Cli("submit " + urdf);
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, AllOf(HasSubstr("triangle inequality"), HasSubstr("--repair")));

  const CommandOutcome repaired = Cli("submit --repair " + urdf);
  ASSERT_EQ(repaired.exit_code, 0) << repaired.output;
  EXPECT_THAT(repaired.output, AllOf(HasSubstr("1 joints"), HasSubstr("repaired:")));

  // The repair is part of the model's content: a sound URDF keeps its id without it.
  const std::string sound =
      Write("sound.urdf",
            OneJointUrdf(R"(<inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/>)"));
  const CommandOutcome plain = Cli("submit " + sound);
  const CommandOutcome with_repair = Cli("submit --repair " + sound);
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  ASSERT_EQ(with_repair.exit_code, 0) << with_repair.output;
  EXPECT_NE(plain.output.substr(0, plain.output.find('\n')),
            with_repair.output.substr(0, with_repair.output.find('\n')));
}

TEST_F(BundleCliTest, SimulateRepairFixesATriangleInequalityDefect) {
  const std::string urdf = Write("odd.urdf", OneJointUrdf(kBrokenInertia));
  const std::string out = (dir_ / "out").string();
  const CommandOutcome refused = Local("simulate " + urdf + " --duration 0.1 --out " + out);
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, AllOf(HasSubstr("triangle inequality"), HasSubstr("--repair")));
  EXPECT_FALSE(fs::exists(dir_ / "out" / "joints.csv"));

  const CommandOutcome repaired =
      Local("simulate --repair " + urdf + " --duration 0.1 --out " + out);
  ASSERT_EQ(repaired.exit_code, 0) << repaired.output;
  EXPECT_THAT(repaired.output, HasSubstr("repaired:"));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "joints.csv"));
}

}  // namespace
}  // namespace mbstream::testing
