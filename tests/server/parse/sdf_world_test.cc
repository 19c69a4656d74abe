// SDFormat worlds (issue 43, docs/worlds.md): several models inline and through <include> of
// model://, each at its <pose>; static models welded where they stand; names scoped
// MODEL::NAME; an include that is not found named with its file, the line of its <uri> and
// the places tried; the server's reading refuses every include.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "server/parse/sdf_import.h"
#include "server/parse/urdf_import.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> JointNamesOf(const Model& model) {
  std::vector<std::string> names;
  for (const Body& body : model.bodies) names.push_back(body.joint.name);
  return names;
}

// A pendulum: a link "bob" on a revolute joint "hinge" (about y) to the world, 0.5 m up.
std::string PendulumModel(const std::string& name, const std::string& pose = "") {
  return "<model name=\"" + name + "\">" + pose +
         "<link name=\"bob\"><pose>0 0 0.5 0 0 0</pose><inertial><mass>2</mass></inertial>"
         "</link>"
         "<joint name=\"hinge\" type=\"revolute\"><parent>world</parent><child>bob</child>"
         "<axis><xyz>0 1 0</xyz></axis></joint></model>";
}

std::string World(const std::string& models) {
  return "<?xml version=\"1.0\"?>\n<sdf version=\"1.8\">\n<world name=\"w\">\n" + models +
         "\n</world>\n</sdf>\n";
}

const std::string kTable =
    "<model name=\"table\"><static>true</static><pose>1 0 0 0 0 1.5707963267948966</pose>"
    "<link name=\"top\"><pose>0.2 0 0.7 0 0 0</pose></link>"
    "<link name=\"leg\"><pose>0 0 0.35 0 0 0</pose></link></model>";

TEST(SdfWorldTest, ModelsOfAWorldAreNamedByModelAndPlacedAtTheirPoses) {
  const SdfImport sdf =
      ImportSdf(World(PendulumModel("left", "<pose>0 -1 0 0 0 0</pose>") +
                      PendulumModel("right", "<pose>0 1 0 0 0 3.141592653589793</pose>") + kTable),
                "w.sdf");
  const Model& model = sdf.model;
  EXPECT_EQ(model.name, "w");
  EXPECT_EQ(JointNamesOf(model), (std::vector<std::string>{"left::hinge", "right::hinge"}));
  // Each hinge's frame is its link's (the joint's default pose), in the world.
  const Body& left = model.bodies[model.FindBody("left::bob")];
  EXPECT_LT((left.joint.X_PJ.p - Vector3d(0, -1, 0.5)).norm(), 1e-12);
  EXPECT_LT((left.joint.axis - Vector3d::UnitY()).norm(), 1e-12);
  const Body& right = model.bodies[model.FindBody("right::bob")];
  EXPECT_LT((right.joint.X_PJ.p - Vector3d(0, 1, 0.5)).norm(), 1e-12);
  // Turned half a turn about z: the joint frame is turned with it, the axis in it the same.
  EXPECT_LT((right.joint.X_PJ.R * Vector3d::UnitX() - Vector3d(-1, 0, 0)).norm(), 1e-12);
  EXPECT_LT((right.joint.axis - Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(model.TotalMass(), 4.0);
  // The static table: its links fixed to the world where they stand (turned a quarter turn
  // about z at x = 1: its top's 0.2 m along x lands along y).
  const int top = model.FindFrame("table::top");
  ASSERT_GE(top, 0);
  EXPECT_EQ(model.frames[top].body, kBase);
  EXPECT_LT((model.frames[top].X_BF.p - Vector3d(1, 0.2, 0.7)).norm(), 1e-12);
  EXPECT_GE(model.FindFrame("table::leg"), 0);
  EXPECT_TRUE(sdf.loops.empty());
  EXPECT_TRUE(sdf.warnings.empty()) << sdf.warnings.front();
}

TEST(SdfWorldTest, AWorldOfOneModelKeepsItsNamesAndAStaticModelsJointsAreWarnedOf) {
  const SdfImport one = ImportSdf(World(PendulumModel("only")), "w.sdf");
  EXPECT_EQ(one.model.name, "only");
  EXPECT_EQ(JointNamesOf(one.model), (std::vector<std::string>{"hinge"}));
  std::string fixed = PendulumModel("still");
  fixed.insert(fixed.find('>') + 1, "<static>true</static>");
  const SdfImport still = ImportSdf(World(fixed + kTable), "w.sdf");
  EXPECT_EQ(still.model.num_dofs(), 0);
  ASSERT_EQ(still.warnings.size(), 1u);
  EXPECT_NE(still.warnings[0].find("w.sdf:4: joint 'still::hinge' moves nothing: its model is "
                                   "static"),
            std::string::npos)
      << still.warnings[0];
}

TEST(SdfWorldTest, ANestedModelsNamesAreScopedAndItsPoseComposes) {
  const std::string outer = "<model name=\"cell\"><pose>2 0 0 0 0 0</pose>" +
                            PendulumModel("arm", "<pose>0 0 1 0 0 0</pose>") + "</model>";
  const SdfImport sdf = ImportSdf(World(outer + kTable), "w.sdf");
  EXPECT_EQ(JointNamesOf(sdf.model), (std::vector<std::string>{"cell::arm::hinge"}));
  const Body& bob = sdf.model.bodies[0];
  EXPECT_LT((bob.joint.X_PJ.p - Vector3d(2, 0, 1.5)).norm(), 1e-12);
}

// A model with no joint to the world moves freely: its canonical link on a free joint named
// after the link, starting at its pose; its other links hang from it by their joints.
TEST(SdfWorldTest, AModelWithNoJointToTheWorldIsAFreeBody) {
  const std::string box =
      "<model name=\"box\"><pose>1 2 3 0 0 1.5707963267948966</pose>"
      "<link name=\"link\"><inertial><mass>1</mass></inertial></link>"
      "<link name=\"lid\"><pose>0 0 0.1 0 0 0</pose><inertial><mass>0.5</mass></inertial></link>"
      "<joint name=\"hinge\" type=\"revolute\"><parent>link</parent><child>lid</child>"
      "<axis><xyz>1 0 0</xyz></axis></joint></model>";
  const SdfImport sdf = ImportSdf(World(box + kTable), "w.sdf");
  const Model& model = sdf.model;
  EXPECT_EQ(JointNamesOf(model), (std::vector<std::string>{"box::link", "box::hinge"}));
  const Body& free = model.bodies[0];
  EXPECT_TRUE(free.free());
  EXPECT_LT((free.X_W0.p - Vector3d(1, 2, 3)).norm(), 1e-12);
  EXPECT_LT((free.X_W0.R * Vector3d::UnitX() - Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_EQ(model.bodies[1].parent, 0);
  EXPECT_LT((model.bodies[1].joint.X_PJ.p - Vector3d(0, 0, 0.1)).norm(), 1e-12);
  EXPECT_EQ(model.nq(), 7 + 1);
  EXPECT_EQ(model.nv(), 6 + 1);
  // A top-level model with no joint to the world is free too (the SDFormat specification).
  const SdfImport alone =
      ImportSdf("<?xml version=\"1.0\"?>\n<sdf version=\"1.8\">\n" + box + "\n</sdf>\n", "box.sdf");
  EXPECT_EQ(JointNamesOf(alone.model), (std::vector<std::string>{"link", "hinge"}));
  EXPECT_TRUE(alone.model.bodies[0].free());
}

// The example world (models/worlds/irb1600_table/): the robot's six joints, then the three
// boxes' free joints; the table a frame of the world.
TEST(SdfWorldTest, TheExampleWorldHoldsTheRobotTheTableAndThreeFreeBoxes) {
  const SdfImport sdf =
      ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/models/worlds/irb1600_table/world.sdf");
  const Model& model = sdf.model;
  EXPECT_EQ(model.name, "irb1600_table");
  EXPECT_EQ(JointNamesOf(model),
            (std::vector<std::string>{"irb1600::joint1", "irb1600::joint2", "irb1600::joint3",
                                      "irb1600::joint4", "irb1600::joint5", "irb1600::joint6",
                                      "box_a::link", "box_b::link", "box_c::link"}));
  EXPECT_EQ(model.nq(), 6 + 3 * 7);
  EXPECT_EQ(model.nv(), 6 + 3 * 6);
  EXPECT_DOUBLE_EQ(model.TotalMass(), 250.0 + 3.0);  // the robot's moving links and the boxes
  ASSERT_GE(model.tcp_frame, 0);
  EXPECT_EQ(model.frames[model.tcp_frame].name, "irb1600::tcp");
  EXPECT_EQ(model.frames[model.FindFrame("table::top")].body, kBase);
  EXPECT_TRUE(sdf.warnings.empty()) << sdf.warnings.front();
  // The robot is models/irb1600/irb1600.urdf's, frame for frame (generate.py writes it).
  const UrdfImport urdf =
      ImportUrdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/models/irb1600/irb1600.urdf");
  for (int i = 0; i < 6; ++i) {
    const Body& a = model.bodies[i];
    const Body& b = urdf.model.bodies[i];
    EXPECT_EQ(a.joint.name, "irb1600::" + b.joint.name);
    EXPECT_LT((a.joint.X_PJ.p - b.joint.X_PJ.p).norm(), 1e-12) << i;
    EXPECT_LT((a.joint.X_PJ.R - b.joint.X_PJ.R).norm(), 1e-12) << i;
    EXPECT_LT((a.joint.axis - b.joint.axis).norm(), 1e-12) << i;
    EXPECT_DOUBLE_EQ(a.inertia.mass, b.inertia.mass) << i;
    EXPECT_LT((a.inertia.com - b.inertia.com).norm(), 1e-12) << i;
    EXPECT_LT((a.inertia.inertia_com - b.inertia.inertia_com).norm(), 1e-12) << i;
    EXPECT_DOUBLE_EQ(a.joint.limits.upper, b.joint.limits.upper) << i;
  }
  const Frame& tcp = model.frames[model.tcp_frame];
  const Frame& urdf_tcp = urdf.model.frames[urdf.model.tcp_frame];
  EXPECT_LT((tcp.X_BF.p - urdf_tcp.X_BF.p).norm(), 1e-12);
}

class SdfIncludeTest : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mbstream_sdf_include_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "models" / "pendulum");
    Write("models/pendulum/model.config",
          "<?xml version=\"1.0\"?><model><name>pendulum</name>"
          "<sdf version=\"1.8\">model.sdf</sdf></model>\n");
    Write("models/pendulum/model.sdf", "<?xml version=\"1.0\"?>\n<sdf version=\"1.8\">\n" +
                                           PendulumModel("pendulum") + "\n</sdf>\n");
  }
  void TearDown() override { fs::remove_all(dir_); }

  void Write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
  }

  fs::path dir_;
};

TEST_F(SdfIncludeTest, AModelIsIncludedTwiceUnderTwoNamesAtTwoPoses) {
  Write("models/world.sdf",
        World("<include><uri>model://pendulum</uri><name>p1</name><pose>1 0 0 0 0 0</pose>"
              "</include>\n"
              "<include><uri>model://pendulum</uri><name>p2</name><pose>-1 0 0 0 0 0</pose>"
              "</include>"));
  const SdfImport sdf = ImportSdfFile((dir_ / "models/world.sdf").string());
  EXPECT_EQ(JointNamesOf(sdf.model), (std::vector<std::string>{"p1::hinge", "p2::hinge"}));
  EXPECT_LT((sdf.model.bodies[0].joint.X_PJ.p - Vector3d(1, 0, 0.5)).norm(), 1e-12);
  EXPECT_LT((sdf.model.bodies[1].joint.X_PJ.p - Vector3d(-1, 0, 0.5)).norm(), 1e-12);
  // Found beside an ancestor too (the world in a subfolder of the models' folder), and a
  // folder with only a model.sdf will do.
  fs::create_directories(dir_ / "models/worlds/one");
  fs::remove(dir_ / "models/pendulum/model.config");
  Write("models/worlds/one/world.sdf",
        World("<include><uri>model://pendulum</uri></include>" + kTable));
  const SdfImport deep = ImportSdfFile((dir_ / "models/worlds/one/world.sdf").string());
  EXPECT_EQ(JointNamesOf(deep.model), (std::vector<std::string>{"pendulum::hinge"}));
}

TEST_F(SdfIncludeTest, AnIncludeNotFoundIsNamedWithItsLineAndThePlacesTried) {
  Write("models/world.sdf",
        World(kTable + "\n<include>\n  <uri>model://no_such_model</uri>\n</include>"));
  try {
    ImportSdfFile((dir_ / "models/world.sdf").string());
    ADD_FAILURE() << "imported";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind((dir_ / "models/world.sdf").string() + ":6: <include> of "
                                                                   "'model://no_such_model': "
                                                                   "not found; tried ",
                            0),
              0u)
        << message;
    EXPECT_NE(message.find((dir_ / "models/no_such_model/model.config").string()),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("give --package-path DIR"), std::string::npos) << message;
  }
}

TEST_F(SdfIncludeTest, AnErrorInsideAnIncludedModelNamesThatFile) {
  Write("models/pendulum/model.sdf",
        "<?xml version=\"1.0\"?>\n<sdf version=\"1.8\">\n<model name=\"pendulum\">\n"
        "<link name=\"bob\"/>\n<joint name=\"j\" type=\"screw\"><parent>world</parent>"
        "<child>bob</child></joint>\n</model>\n</sdf>\n");
  Write("models/world.sdf", World("<include><uri>model://pendulum</uri></include>" + kTable));
  try {
    ImportSdfFile((dir_ / "models/world.sdf").string());
    ADD_FAILURE() << "imported";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find((dir_ / "models/pendulum/model.sdf").string() +
                           ":5: joint 'pendulum::j': this joint type is not simulated"),
              std::string::npos)
        << message;
  }
}

// The server reads no file a model names: `mbstream submit` sends the world with its
// included models written into it (model_files::SdfFile::ExpandedText), which imports alike.
TEST_F(SdfIncludeTest, TheServersReadingRefusesAnIncludeAndReadsTheExpandedWorld) {
  const std::string world = World(
      "<include><uri>model://pendulum</uri><name>p1</name><pose>1 0 0 0 0 0</pose>"
      "</include>" +
      kTable);
  try {
    ImportSdf(world, "w.sdf");
    ADD_FAILURE() << "imported";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("w.sdf:4: <include> is not read by mbstream: the "
                        "server reads no file a model names"),
              std::string::npos)
        << error.what();
  }
  const model_files::SdfFile local(world, "w.sdf",
                                   {.includes = model_files::SdfIncludePath{dir_ / "models"}});
  const std::string expanded = local.ExpandedText();
  EXPECT_EQ(expanded.find("<include"), std::string::npos) << expanded;
  const SdfImport sdf = ImportSdf(expanded, "w.sdf");
  EXPECT_EQ(JointNamesOf(sdf.model), (std::vector<std::string>{"p1::hinge"}));
  EXPECT_LT((sdf.model.bodies[0].joint.X_PJ.p - Vector3d(1, 0, 0.5)).norm(), 1e-12);
  EXPECT_GE(sdf.model.FindFrame("table::top"), 0);
}

// A mesh an included model names relative to its own file is named from the world once the
// includes are read (shared/model_files/sdf_mesh_uris.h): model://NAME/... for a model found
// by model://NAME (beside the world, or in the package path), a path relative to the world's
// folder for one included by a relative path, file:///abs for one outside the world's folder.
// A model:// URI and the world's own relative paths stay as written.
TEST_F(SdfIncludeTest, AnIncludedModelsRelativeMeshPathIsNamedFromTheWorld) {
  const auto model = [](const std::string& name, const std::string& mesh) {
    return "<?xml version=\"1.0\"?>\n<sdf version=\"1.8\">\n<model name=\"" + name +
           "\"><static>true</static><link name=\"l\"><visual name=\"v\"><geometry><mesh><uri>" +
           mesh + "</uri></mesh></geometry></visual><collision name=\"c\"><geometry><mesh><uri>" +
           mesh + "</uri></mesh></geometry></collision></link></model>\n</sdf>\n";
  };
  const auto folder = [&](const std::string& path, const std::string& name,
                          const std::string& mesh) {
    fs::create_directories(dir_ / path);
    Write(path + "/model.config", "<?xml version=\"1.0\"?><model><name>" + name +
                                      "</name><sdf version=\"1.8\">model.sdf</sdf></model>\n");
    Write(path + "/model.sdf", model(name, mesh));
  };
  folder("models/post", "post", "meshes/post.stl");
  folder("packages/grippers/gripper", "gripper", "./meshes/../meshes/finger.dae");
  folder("models/parts/plate", "plate", "plate.obj");
  folder("outside/lid", "lid", "meshes/lid.stl");
  folder("models/cup", "cup", "model://cup/meshes/cup.stl");
  const std::string world = World(
      "<include><uri>model://post</uri></include>\n"
      "<include><uri>model://gripper</uri></include>\n"
      "<include><uri>parts/plate</uri></include>\n"
      "<include><uri>../outside/lid</uri></include>\n"
      "<include><uri>model://cup</uri></include>\n"
      "<model name=\"own\"><static>true</static><link name=\"l\"><visual name=\"v\"><geometry>"
      "<mesh><uri>meshes/own.stl</uri></mesh></geometry></visual></link></model>");
  const model_files::SdfFile file(
      world, (dir_ / "models/world.sdf").string(),
      {.includes = model_files::SdfIncludePath{dir_ / "models", {dir_ / "packages"}}});
  const std::vector<std::string> expected = {
      "model://post/meshes/post.stl", "model://gripper/meshes/finger.dae",
      "parts/plate/plate.obj",        "file://" + (dir_ / "outside/lid/meshes/lid.stl").string(),
      "model://cup/meshes/cup.stl",   "meshes/own.stl"};
  const model_files::SdfMeshes meshes = model_files::MeshesOf(file);
  EXPECT_EQ(meshes.visual, expected);
  EXPECT_EQ(meshes.collision, std::vector<std::string>(expected.begin(), expected.end() - 1));
  // `mbstream submit` sends the expanded world: it names them alike.
  const model_files::SdfMeshes sent = model_files::ReadSdfMeshes(file.ExpandedText());
  EXPECT_EQ(sent.visual, expected);
}

}  // namespace
}  // namespace mbstream
