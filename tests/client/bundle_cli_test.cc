// Model bundles as a user submits them: `mbstream submit` and `mbstream simulate` on small
// robots written by the tests (--repair, description folders with package:// meshes),
// against a real mbstream-server.
#include <gmock/gmock.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "tests/common/cli_server_test.h"

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

// A ROS-style description folder: package.xml naming `package`, urdf/robot.urdf with
// package:// meshes (visual and collision meshes of base_link share the base name
// link0.stl) and a relative one; with `missing`, a visual mesh that is not on disk.
void WriteDescription(const fs::path& folder, const std::string& package, bool missing) {
  const auto write = [&](const std::string& relative, const std::string& text) {
    fs::create_directories((folder / relative).parent_path());
    std::ofstream(folder / relative, std::ios::binary) << text;
  };
  write("package.xml", "<package format=\"3\"><name>" + package + "</name></package>\n");
  for (const char* mesh : {"meshes/visual/link0.stl", "meshes/visual/link1.stl"}) {
    write(mesh, std::string("solid ") + mesh + "\nendsolid\n");
  }
  // The collision mesh a tetrahedron: contact takes its convex hull.
  std::string tetrahedron = "solid tetrahedron\n";
  const char* corners[4] = {"0 0 0", "0.1 0 0", "0 0.1 0", "0 0 0.1"};
  for (const auto& face : {"021", "013", "032", "123"}) {
    tetrahedron += " facet normal 0 0 0\n  outer loop\n";
    for (int k = 0; k < 3; ++k)
      tetrahedron += std::string("   vertex ") + corners[face[k] - '0'] + "\n";
    tetrahedron += "  endloop\n endfacet\n";
  }
  write("meshes/collision/link0.stl", tetrahedron + "endsolid tetrahedron\n");
  const std::string p = "package://" + package + "/meshes/";
  write("urdf/robot.urdf", R"(<robot name="described">
  <link name="base_link">
    <visual><geometry><mesh filename=")" +
                               p + R"(visual/link0.stl"/></geometry></visual>
    <collision><geometry><mesh filename=")" +
                               p + R"(collision/link0.stl"/></geometry></collision>
  </link>
  <link name="arm"><inertial><mass value="2"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="../meshes/visual/link1.stl"/></geometry></visual>)" +
                               std::string(missing ? R"(
    <visual><geometry><mesh filename=")" + p + R"(visual/absent.dae"/></geometry></visual>)"
                                                   : "") +
                               R"(
  </link>
  <joint name="j1" type="revolute"><parent link="base_link"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
)");
}

class BundleCliTest : public CliServerTest {
 protected:
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

TEST_F(BundleCliTest, SubmitFolderAttachesItsMeshesAndCollisionOnesOnRequest) {
  StartServer();
  WriteDescription(dir_ / "renamed_description", "demo_description", false);
  const std::string folder = (dir_ / "renamed_description").string();
  const CommandOutcome visual = Cli("submit " + folder);
  ASSERT_EQ(visual.exit_code, 0) << visual.output;
  // Visual link0.stl and link1.stl; collision link0.stl (same base name) not sent.
  EXPECT_THAT(visual.output, HasSubstr(", 2 assets"));
  EXPECT_THAT(visual.output, Not(HasSubstr("visual mesh")));
  EXPECT_THAT(visual.output, HasSubstr("1 collision mesh(es) not supplied"));

  const CommandOutcome collision = Cli("submit --with-collision " + folder);
  ASSERT_EQ(collision.exit_code, 0) << collision.output;
  EXPECT_THAT(collision.output, HasSubstr(", 3 assets"));
  // Every mesh sent: none is missing. The collision mesh is simulated: its convex hull (a
  // tetrahedron, convex: no warning; docs/contact.md).
  EXPECT_THAT(collision.output, AllOf(Not(HasSubstr("not supplied")), Not(HasSubstr("not found")),
                                      Not(HasSubstr("asset '"))));
  EXPECT_THAT(collision.output, AllOf(Not(HasSubstr("not simulated")),
                                      Not(HasSubstr("touch nothing")), Not(HasSubstr("convex"))));
  EXPECT_NE(visual.output.substr(0, visual.output.find('\n')),
            collision.output.substr(0, collision.output.find('\n')));

  // The same URDF copied elsewhere finds its package through --package-path.
  fs::create_directories(dir_ / "generated");
  fs::copy_file(dir_ / "renamed_description/urdf/robot.urdf", dir_ / "generated/robot.urdf");
  const CommandOutcome lost = Cli("submit " + (dir_ / "generated/robot.urdf").string());
  ASSERT_EQ(lost.exit_code, 0) << lost.output;
  // The server says the missing visual meshes once, as a count (issue 32).
  EXPECT_THAT(lost.output, AllOf(HasSubstr(", 0 assets"), HasSubstr("was not found; tried"),
                                 HasSubstr("2 visual meshes are not supplied")));
  const CommandOutcome found = Cli("submit " + (dir_ / "generated/robot.urdf").string() +
                                   " --package-path " + dir_.string());
  ASSERT_EQ(found.exit_code, 0) << found.output;
  EXPECT_THAT(found.output, HasSubstr(", 1 assets"));  // link0 by package; ../meshes is not
}

TEST_F(BundleCliTest, MissingVisualMeshIsAWarningOnSubmitAndSimulateNeedsNoMeshes) {
  StartServer();
  WriteDescription(dir_ / "demo_description", "demo_description", true);
  const CommandOutcome submit = Cli("submit " + (dir_ / "demo_description").string());
  ASSERT_EQ(submit.exit_code, 0) << submit.output;
  EXPECT_THAT(submit.output,
              AllOf(HasSubstr("'package://demo_description/meshes/visual/absent.dae' was not "
                              "found; tried"),
                    HasSubstr("link 'arm': visual mesh "
                              "'package://demo_description/meshes/visual/absent.dae' is not "
                              "supplied"),
                    HasSubstr(", 2 assets")));

  // simulate: no mesh at all on disk.
  const std::string urdf =
      Write("bare/robot.urdf", ReadTextFile((dir_ / "demo_description/urdf/robot.urdf").string()));
  const CommandOutcome simulate =
      Local("simulate " + urdf + " --duration 0.1 --out " + (dir_ / "out").string());
  ASSERT_EQ(simulate.exit_code, 0) << simulate.output;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "joints.csv"));
}

TEST_F(BundleCliTest, XacroIsRefusedWithTheCommandThatExpandsIt) {
  const std::string xacro = Write("robot/model.urdf.xacro", "<robot/>");
  StartServer();
  const CommandOutcome submit = Cli("submit " + xacro);
  EXPECT_EQ(submit.exit_code, 2) << submit.output;
  EXPECT_THAT(submit.output, HasSubstr("xacro " + xacro + " > model.urdf"));
}

}  // namespace
}  // namespace mbstream::testing
