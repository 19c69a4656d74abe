// The viewer draws the SDFormat linkages of models/linkages/ (issue 31) as the server reads
// them: the spanning tree's joints in the server's order, every visual (box, cylinder) with
// its <material> colour, at its pose; the actors follow the joints. Under a private Xvfb.
#include <gtest/gtest.h>

#include <vtkActor.h>
#include <vtkProperty.h>

#include <array>
#include <cmath>
#include <map>

#include "shared/common/check.h"
#include "tests/viewer/xvfb_display.h"
#include "viewer/model/model_scene.h"
#include "viewer/scene/scene.h"

namespace mbstream::viewer {
namespace {

using Eigen::Vector3d;

std::array<int, 3> Rgb(vtkActor* actor) {
  const double* c = actor->GetProperty()->GetColor();
  return {int(std::lround(c[0] * 100)), int(std::lround(c[1] * 100)), int(std::lround(c[2] * 100))};
}

Eigen::AlignedBox3d WorldBounds(vtkActor* actor) {
  double b[6];
  actor->GetBounds(b);
  return Eigen::AlignedBox3d(Vector3d(b[0], b[2], b[4]), Vector3d(b[1], b[3], b[5]));
}

std::vector<std::string> JointNames(const KinematicChain& chain) {
  std::vector<std::string> names;
  for (int i = 0; i < chain.dof(); ++i) names.push_back(chain.dof_joint(i).name);
  return names;
}

SceneOptions Offscreen() {
  SceneOptions options;
  options.width = 320;
  options.height = 240;
  options.offscreen = true;
  return options;
}

TEST(SdfScene, TheFourBarsTreeJointsAreTheServersAndItsBarsAreDrawnInTheirColours) {
  const SceneDescription description = SceneFromModelFile("models/linkages/four_bar.sdf");
  EXPECT_EQ(description.title, "four_bar");
  EXPECT_TRUE(description.joints_named_as_model);
  // The server's tree, breadth-first from the world; the cut joint (loop_joint) is no joint
  // of the chain.
  EXPECT_EQ(JointNames(description.chain),
            (std::vector<std::string>{"crank_joint", "rocker_joint", "coupler_joint"}));
  EXPECT_TRUE(description.warnings.empty());
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  Scene scene(description, Offscreen());
  ASSERT_EQ(scene.part_actor_count(), 3);
  const std::vector<double> q = {0.0, 0.0, 0.0};
  scene.SetJointValues(q);
  scene.SyncActors();
  std::map<std::string, vtkActor*> by_link;
  for (size_t k = 0; k < description.visuals.size(); ++k) {
    by_link[description.visuals[k].name] = scene.part_actors()[k];
  }
  EXPECT_EQ(Rgb(by_link.at("crank")), (std::array<int, 3>{80, 20, 20}));
  EXPECT_EQ(Rgb(by_link.at("coupler")), (std::array<int, 3>{20, 50, 90}));
  EXPECT_EQ(Rgb(by_link.at("rocker")), (std::array<int, 3>{20, 70, 30}));
  // As drawn: the crank (0.1 m, 0.02 m square) straight up from the origin.
  const Eigen::AlignedBox3d crank = WorldBounds(by_link.at("crank"));
  EXPECT_LT((crank.min() - Vector3d(-0.01, -0.01, 0.0)).norm(), 1e-9);
  EXPECT_LT((crank.max() - Vector3d(0.01, 0.01, 0.1)).norm(), 1e-9);
  // A quarter turn about -y (+x towards +z) lays the crank from straight up (+z) along -x.
  const std::vector<double> turned = {M_PI / 2, 0.0, 0.0};
  scene.SetJointValues(turned);
  scene.SyncActors();
  const Eigen::AlignedBox3d crank_turned = WorldBounds(by_link.at("crank"));
  EXPECT_LT((crank_turned.min() - Vector3d(-0.1, -0.01, -0.01)).norm(), 1e-9);
  EXPECT_LT((crank_turned.max() - Vector3d(0.0, 0.01, 0.01)).norm(), 1e-9);
}

TEST(SdfScene, TheDeltaRobotsArmsRodsAndPlatformMeetWhereTheyAreDrawn) {
  const SceneDescription description = SceneFromModelFile("models/linkages/delta.sdf");
  EXPECT_EQ(description.title, "delta");
  // 18 tree joints (3 motors, 5 rods by two revolutes each plus rod 1a's, the wrist's 3);
  // the five ball joints are cut.
  ASSERT_EQ(description.chain.dof(), 18);
  EXPECT_EQ(description.chain.dof_joint(0).name, "motor1");
  for (const std::string& name : JointNames(description.chain)) {
    EXPECT_EQ(name.rfind("ball", 0), std::string::npos) << name;
  }
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  Scene scene(description, Offscreen());
  ASSERT_EQ(scene.part_actor_count(), 10);  // the platform, 3 arms, 6 rods
  scene.SetJointValues(std::vector<double>(18, 0.0));
  scene.SyncActors();
  std::map<std::array<int, 3>, int> colours;
  for (const auto& actor : scene.part_actors()) ++colours[Rgb(actor)];
  EXPECT_EQ(colours, (std::map<std::array<int, 3>, int>{
                         {{80, 30, 10}, 3}, {{60, 60, 65}, 6}, {{20, 40, 80}, 1}}));
  for (size_t k = 0; k < description.visuals.size(); ++k) {
    const std::string& link = description.visuals[k].name;
    const Eigen::AlignedBox3d box = WorldBounds(scene.part_actors()[k]);
    if (link == "platform") {
      // A disc of radius 0.05 m, 0.01 m thick, 0.45 m below the base.
      EXPECT_LT((box.center() - Vector3d(0, 0, -0.45)).norm(), 1e-9);
      EXPECT_NEAR(box.sizes().x(), 0.1, 1e-3);
      EXPECT_NEAR(box.sizes().z(), 0.01, 1e-9);
    } else if (link.rfind("arm", 0) == 0) {
      // From the base circle (radius 0.2 m, z = 0) outwards and down.
      EXPECT_NEAR(box.max().z(), 0.0, 0.013) << link;
      EXPECT_GT(box.min().z(), -0.25) << link;
    } else {
      // Each rod (0.5 m) hangs from its arm's end down to the platform's rim.
      ASSERT_EQ(link.rfind("rod", 0), 0u) << link;
      EXPECT_NEAR(box.min().z(), -0.45, 0.007) << link;
      EXPECT_GT(box.max().z(), -0.25) << link;
    }
  }
  // The platform follows the tree (rod 1a, then the wrist): turning motor 1 moves it.
  std::vector<double> q(18, 0.0);
  q[0] = 0.1;
  scene.SetJointValues(q);
  scene.SyncActors();
  for (size_t k = 0; k < description.visuals.size(); ++k) {
    if (description.visuals[k].name != "platform") continue;
    EXPECT_GT((WorldBounds(scene.part_actors()[k]).center() - Vector3d(0, 0, -0.45)).norm(), 0.01);
  }
}

TEST(SdfScene, ErrorsAreTheServersWithFileAndLine) {
  const std::string universal =
      "<sdf version=\"1.7\"><model name=\"m\">\n"
      "<link name=\"a\"/>\n"
      "<joint name=\"j\" type=\"universal\"><parent>world</parent><child>a</child></joint>\n"
      "</model></sdf>\n";
  try {
    SceneFromModelText(universal, "m.sdf",
                       [](const std::string&) { return std::filesystem::path(); });
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(
                  "m.sdf:3: joint 'j': this joint type is not simulated by mbstream", 0),
              0u)
        << e.what();
  }
}

TEST(SdfScene, AMissingMeshIsAPlaceholderAndAFoundOneIsDrawnFromItsFile) {
  const std::string text =
      "<sdf version=\"1.7\"><model name=\"m\">\n"
      "<link name=\"a\"><visual name=\"v\"><geometry><mesh><uri>model://m/meshes/a.stl</uri>"
      "<scale>2 2 2</scale></mesh></geometry></visual>\n"
      "<visual name=\"w\"><geometry><mesh><uri>meshes/missing.stl</uri></mesh></geometry>"
      "<material><ambient>0 1 0 1</ambient></material></visual></link>\n"
      "<joint name=\"j\" type=\"revolute\"><parent>world</parent><child>a</child>"
      "<axis><xyz>0 0 1</xyz></axis></joint>\n"
      "</model></sdf>\n";
  const SceneDescription scene =
      SceneFromModelText(text, "m.sdf", [](const std::string& uri) -> std::filesystem::path {
        return uri == "model://m/meshes/a.stl" ? "/found/a.stl" : "";
      });
  ASSERT_EQ(scene.visuals.size(), 2u);
  const auto* file = std::get_if<MeshFile>(&scene.visuals[0].geometry);
  ASSERT_NE(file, nullptr);
  EXPECT_EQ(file->path, "/found/a.stl");
  EXPECT_TRUE(file->file_colours);  // no <material>: the file's own colours
  EXPECT_EQ(scene.visuals[0].scale, Vector3d(2, 2, 2));
  EXPECT_TRUE(scene.visuals[1].placeholder);
  EXPECT_EQ(scene.visuals[1].mesh_filename, "meshes/missing.stl");
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_EQ(scene.warnings[0].rfind("m.sdf:3: link 'a': mesh 'meshes/missing.stl' is not found", 0),
            0u)
      << scene.warnings[0];
}

}  // namespace
}  // namespace mbstream::viewer
