// SDFormat linkages with closed loops through a live mbstream-server (issue 31): submitted
// like a URDF, run with the loops held, and the same files as `mbstream simulate`, bit for
// bit, the cut joints' columns included; a URDF <mimic> held with --couple-mimic.
#include <gmock/gmock.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "tests/common/cli_server_test.h"
#include "tests/common/csv_rows.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

class ServerLoopsCliTest : public CliServerTest {
 protected:
  void SetUp() override {
    CliServerTest::SetUp();
    StartServer();
  }
  CommandOutcome Simulate(const std::string& args) {
    return RunCommand(std::string(MBSTREAM_CLI) + " simulate " + args);
  }
};

// The server's files of a run against simulate's: every file the run writes.
void ExpectSameFiles(const fs::path& served, const fs::path& local) {
  for (const char* file :
       {"joints.csv", "velocities.csv", "tcp.csv", "torques.csv", "energy.csv"}) {
    ASSERT_EQ(fs::exists(served / file), fs::exists(local / file)) << file;
    if (!fs::exists(local / file)) continue;
    const std::string text = ReadFile(served / file);
    EXPECT_FALSE(text.empty()) << file;
    EXPECT_EQ(text, ReadFile(local / file)) << file << " differs";
  }
}

TEST_F(ServerLoopsCliTest, SubmittedSdfRunsGiveTheSameFilesAsSimulate) {
  const CommandOutcome submit = Cli("submit models/linkages/four_bar.sdf --name four_bar");
  ASSERT_EQ(submit.exit_code, 0) << submit.output;
  EXPECT_THAT(submit.output, HasSubstr("3 joints"));  // the tree's moving joints

  // Passive (the projected ODE) and driven (kinematic): both the same as simulate.
  for (const std::string spec : {"four_bar-passive", "four_bar-driven"}) {
    const std::string spec_file = " --spec models/linkages/" + spec + ".json";
    const CommandOutcome run = Cli("run four_bar" + spec_file + " --watch --out " + Out(spec));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(FirstLine(run.output).substr(0, 2), "r-");
    EXPECT_THAT(run.output, HasSubstr("loop residual"));
    const CommandOutcome local =
        Simulate("models/linkages/four_bar.sdf" + spec_file + " --out " + Out(spec + "-local"));
    ASSERT_EQ(local.exit_code, 0) << local.output;
    ExpectSameFiles(dir_ / spec, dir_ / (spec + "-local"));
    // Every joint of the file, the cut joint last; its loop on the wire into stats.json.
    EXPECT_EQ(FirstLine(ReadFile(dir_ / spec / "velocities.csv")),
              "t,crank_joint,rocker_joint,coupler_joint,loop_joint");
    const std::string stats = ReadFile(dir_ / spec / "stats.json");
    EXPECT_THAT(stats, HasSubstr("\"cut_joints\": [\n      \"loop_joint (revolute)\""));
    EXPECT_THAT(stats, HasSubstr("\"mobility\": 1"));
  }
}

// A URDF whose second joint follows the first (<mimic>): submitted with --couple-mimic the
// server holds the coupling (its own model id; the same files as simulate --couple-mimic);
// without, the joint moves freely and the submit warns.
TEST_F(ServerLoopsCliTest, AUrdfMimicIsHeldWhenSubmittedWithCoupleMimic) {
  const std::string inertial = R"(<inertial><origin xyz="0 0 -0.3"/><mass value="1"/>
      <inertia ixx="0.03" iyy="0.03" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial>)";
  std::ofstream(dir_ / "rods.urdf") << R"(<robot name="rods"><link name="base"/>
  <link name="a">)" << inertial << R"(</link><link name="b">)"
                                    << inertial << R"(</link>
  <joint name="ja" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 1 0"/>
  </joint>
  <joint name="jb" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 1 0"/>
    <origin xyz="0 0 -0.1"/><mimic joint="ja" multiplier="-0.5" offset="0.25"/></joint>
</robot>)";
  std::ofstream(dir_ / "swing.json")
      << R"({"duration_s": 1, "output_interval_s": 0.05, "formulation": "joint",
             "method": "bdf", "rtol": 1e-9, "atol": 1e-11, "initial_q": [1.0, 0.0]})";
  const CommandOutcome free = Cli("submit " + Out("rods.urdf") + " --name rods_free");
  ASSERT_EQ(free.exit_code, 0) << free.output;
  EXPECT_THAT(free.output, HasSubstr("<mimic> of joint 'ja' is ignored"));
  const CommandOutcome coupled = Cli("submit " + Out("rods.urdf") + " --couple-mimic");
  ASSERT_EQ(coupled.exit_code, 0) << coupled.output;
  EXPECT_THAT(coupled.output, Not(HasSubstr("mimic")));
  EXPECT_NE(FirstLine(coupled.output), FirstLine(free.output));  // another model id

  const CommandOutcome run = Cli("run " + FirstLine(coupled.output) + " --spec " +
                                 Out("swing.json") + " --watch --out " + Out("served"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const CommandOutcome local = Simulate(Out("rods.urdf") + " --couple-mimic --spec " +
                                        Out("swing.json") + " --out " + Out("local"));
  ASSERT_EQ(local.exit_code, 0) << local.output;
  ExpectSameFiles(dir_ / "served", dir_ / "local");
  EXPECT_THAT(ReadFile(dir_ / "served" / "stats.json"),
              HasSubstr("\"cut_joints\": [\n      \"jb (mimic)\""));
  const std::vector<std::vector<std::string>> joints = ReadCsv(dir_ / "served" / "joints.csv");
  ASSERT_EQ(joints.size(), 21u);
  for (const auto& row : joints) {
    EXPECT_NEAR(std::stod(row[2]), -0.5 * std::stod(row[1]) + 0.25, 1e-8) << "t = " << row[0];
  }
  EXPECT_LT(std::stod(joints.back()[1]), 0.9);  // it swung
}

// The cut joints' reactions (RunSpec.report_loop_forces) from a server run: `mbstream run
// --out` (GetResult) writes loop_forces.csv as simulate does, bit for bit, beside the drive
// efforts of a driven run (Frame.tau carries both), from the joint-space ODE and DAE, the body
// DAE and the kinematic run.
TEST_F(ServerLoopsCliTest, LoopReactionsOfAServerRunAreTheSameAsSimulate) {
  const std::string spec_dir = Out("specs");
  fs::create_directories(spec_dir);
  struct Case {
    std::string name;
    std::string spec;
  };
  const std::vector<Case> cases = {
      {"passive", R"({"duration_s": 0.5, "output_interval_s": 0.01, "formulation": "joint",
          "method": "bdf", "rtol": 1e-8, "atol": 1e-10, "report_loop_forces": true})"},
      {"dae", R"({"duration_s": 0.5, "output_interval_s": 0.01, "formulation": "joint",
          "method": "ida", "rtol": 1e-7, "atol": 1e-9, "report_loop_forces": true})"},
      {"body", R"({"duration_s": 0.5, "output_interval_s": 0.01, "formulation": "body-index2",
          "method": "ida", "rtol": 1e-8, "atol": 1e-10, "report_loop_forces": true})"},
      {"driven", ReadFile("models/linkages/four_bar-driven.json")
                     .insert(1, "\"report_loop_forces\": true, ")},
  };
  for (const Case& c : cases) {
    const std::string spec = spec_dir + "/" + c.name + ".json";
    std::ofstream(spec) << c.spec;
    const CommandOutcome run = Cli("run four_bar --spec " + spec + " --watch --out " + Out(c.name));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const CommandOutcome local =
        Simulate("models/linkages/four_bar.sdf --spec " + spec + " --out " + Out(c.name + "-l"));
    ASSERT_EQ(local.exit_code, 0) << local.output;
    ExpectSameFiles(dir_ / c.name, dir_ / (c.name + "-l"));
    const std::string forces = ReadFile(dir_ / c.name / "loop_forces.csv");
    EXPECT_EQ(forces, ReadFile(dir_ / (c.name + "-l") / "loop_forces.csv")) << c.name;
    EXPECT_EQ(FirstLine(forces),
              "t,loop_joint.fx,loop_joint.fy,loop_joint.fz,loop_joint.tx,loop_joint.ty,"
              "loop_joint.tz");
    EXPECT_TRUE(fs::exists(dir_ / c.name / "torques.csv")) << c.name;  // before the reactions
  }
}

// models/linkages/*.sdf are built-in models (each file one, named after it): run without a
// submit.
TEST_F(ServerLoopsCliTest, TheShippedLinkagesAreBuiltInModels) {
  const CommandOutcome models = Cli("models");
  ASSERT_EQ(models.exit_code, 0) << models.output;
  for (const char* name : {"four_bar", "parallelogram", "slider_crank", "delta", "palletiser"}) {
    EXPECT_THAT(models.output, HasSubstr(name));
  }
  const CommandOutcome run =
      Cli("run palletiser --spec models/linkages/palletiser-driven.json --watch --out " +
          Out("palletiser"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("loop residual"));
  const std::string stats = ReadFile(dir_ / "palletiser" / "stats.json");
  EXPECT_THAT(stats, HasSubstr("\"mobility\": 4"));
  EXPECT_THAT(stats, HasSubstr("\"formulation\": \"kinematic\""));
}

TEST_F(ServerLoopsCliTest, AnSdfModelFolderAndItsModelMeshesAreSubmitted) {
  // A folder with one .sdf whose visual refers to model://bars/meshes/bar.stl: found in
  // the package path like a package:// mesh, and stored.
  const fs::path model = dir_ / "models" / "bars";
  fs::create_directories(model / "meshes");
  std::ofstream(model / "meshes" / "bar.stl") << "solid bar\nendsolid bar\n";
  std::string sdf = ReadFile("models/linkages/slider_crank.sdf");
  const std::string link = "<link name=\"crank\">";
  const size_t at = sdf.find(link);
  ASSERT_NE(at, std::string::npos);
  sdf.insert(at + link.size(),
             "<visual name=\"mesh\"><geometry><mesh><uri>model://bars/meshes/bar.stl</uri>"
             "</mesh></geometry></visual>");
  std::ofstream(model / "slider_crank.sdf") << sdf;
  const CommandOutcome submit =
      Cli("submit " + model.string() + " --package-path " + (dir_ / "models").string());
  ASSERT_EQ(submit.exit_code, 0) << submit.output;
  EXPECT_THAT(submit.output, HasSubstr("1 assets"));
  EXPECT_THAT(submit.output, Not(HasSubstr("was not found")));

  // Without the package path it is said, with every place tried, and the model still goes.
  fs::rename(dir_ / "models", dir_ / "elsewhere");
  fs::create_directories(model);
  std::ofstream(model / "slider_crank.sdf") << sdf << "\n";  // another content id
  const CommandOutcome missing = Cli("submit " + (model / "slider_crank.sdf").string());
  ASSERT_EQ(missing.exit_code, 0) << missing.output;
  EXPECT_THAT(missing.output, HasSubstr("'model://bars/meshes/bar.stl' was not found"));
  EXPECT_THAT(missing.output, HasSubstr("--package-path"));
}

TEST_F(ServerLoopsCliTest, ABadSdfIsRefusedWithItsLine) {
  std::ofstream(dir_ / "bad.sdf")
      << "<?xml version=\"1.0\"?>\n<sdf version=\"1.7\">\n<model name=\"m\">\n"
         "<link name=\"a\"/>\n<joint name=\"j\" type=\"screw\"><parent>world</parent>"
         "<child>a</child></joint>\n</model>\n</sdf>\n";
  const CommandOutcome submit = Cli("submit " + (dir_ / "bad.sdf").string());
  EXPECT_EQ(submit.exit_code, 2) << submit.output;
  EXPECT_THAT(submit.output, HasSubstr("bad.sdf:5"));
}

}  // namespace
}  // namespace mbstream::testing
