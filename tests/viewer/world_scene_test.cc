// The viewer draws an SDFormat world (issue 43, docs/worlds.md): every model of
// models/worlds/irb1600_table/ (the robot included from its folder, the static table, three
// boxes included from one folder), named as the server names them (MODEL::NAME), the boxes
// posed by their free joints' seven values (position, unit quaternion); a snapshot shows
// each model's colour. Under a private Xvfb.
#include <gtest/gtest.h>

#include <vtkActor.h>

#include <cmath>
#include <map>
#include <set>

#include "shared/common/check.h"
#include "tests/viewer/xvfb_display.h"
#include "viewer/kinematics/pose_solver.h"
#include "viewer/model/model_scene.h"
#include "viewer/scene/scene.h"

namespace mbstream::viewer {
namespace {

using Eigen::Vector3d;

const char kWorld[] = "models/worlds/irb1600_table/world.sdf";

Eigen::AlignedBox3d WorldBounds(vtkActor* actor) {
  double b[6];
  actor->GetBounds(b);
  return Eigen::AlignedBox3d(Vector3d(b[0], b[2], b[4]), Vector3d(b[1], b[3], b[5]));
}

std::vector<std::string> JointNames(const KinematicChain& chain) {
  std::vector<std::string> names;
  for (int i = 0; i < chain.dof(); ++i) {
    if (i == 0 || chain.dof_joint(i).name != names.back()) names.push_back(chain.dof_joint(i).name);
  }
  return names;
}

// The model part of a scoped name: "box_a" of "box_a::link".
std::string ModelOf(const std::string& name) { return name.substr(0, name.find("::")); }

const std::vector<std::string> kJoints = {"irb1600::joint1", "irb1600::joint2", "irb1600::joint3",
                                          "irb1600::joint4", "irb1600::joint5", "irb1600::joint6",
                                          "box_a::link",     "box_b::link",     "box_c::link"};

TEST(WorldScene, EveryModelIsDrawnAndNamedAsTheServerNamesIt) {
  const SceneDescription scene = SceneFromModelFile(kWorld);
  EXPECT_EQ(scene.title, "irb1600_table");
  EXPECT_TRUE(scene.joints_named_as_model);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  // Six revolute joints, then three free joints of seven values each.
  EXPECT_EQ(JointNames(scene.chain), kJoints);
  ASSERT_EQ(scene.chain.dof(), 6 + 3 * 7);
  std::map<std::string, int> visuals;
  for (const VisualPart& part : scene.visuals) ++visuals[ModelOf(part.name)];
  EXPECT_EQ(visuals, (std::map<std::string, int>{
                         {"irb1600", 7}, {"table", 5}, {"box_a", 1}, {"box_b", 1}, {"box_c", 1}}));
  // The boxes start at their <include> poses: box_b turned 0.5 rad about z.
  const std::vector<double> box_b(scene.initial_q.begin() + 13, scene.initial_q.begin() + 20);
  const std::vector<double> expected = {1.1, 0.1, 1.0, std::cos(0.25), 0, 0, std::sin(0.25)};
  for (int k = 0; k < 7; ++k) EXPECT_NEAR(box_b[k], expected[k], 1e-12) << k;
  // The robot's TCP probe, reported in the world.
  ASSERT_EQ(scene.probes.size(), 1u);
  EXPECT_EQ(scene.frame_names[scene.probes[0].frame], "irb1600::tcp");
  EXPECT_EQ(scene.probes[0].refer_name, "world");
}

TEST(WorldScene, TheServersNamesOrderTheValuesAFreeJointByNameOrByItsSevenValues) {
  SceneDescription by_joint = SceneFromModelFile(kWorld);
  std::vector<std::string> names(kJoints.rbegin(), kJoints.rend());  // boxes first
  by_joint.chain.OrderJointValuesBy(names);
  EXPECT_EQ(by_joint.chain.dof_joint(0).name, "box_c::link");
  EXPECT_EQ(by_joint.chain.dof_joint(6).name, "box_c::link");
  EXPECT_EQ(by_joint.chain.dof_joint(21).name, "irb1600::joint6");
  SceneDescription by_value = SceneFromModelFile(kWorld);
  std::vector<std::string> values(kJoints.begin(), kJoints.begin() + 6);
  for (const char* box : {"box_a::link", "box_b::link", "box_c::link"}) {
    for (const char* suffix : {".x", ".y", ".z", ".qw", ".qx", ".qy", ".qz"}) {
      values.push_back(box + std::string(suffix));
    }
  }
  by_value.chain.OrderJointValuesBy(values);
  EXPECT_EQ(by_value.chain.dof_joint(6).name, "box_a::link");
  // A free joint's values apart, or a name the scene lacks, is refused with the names.
  std::swap(values[6], values[7]);
  try {
    by_value.chain.OrderJointValuesBy(values);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("free joint 'box_a::link' has its seven values apart"),
              std::string::npos)
        << error.what();
  }
  names.back() = "irb1600::joint7";
  try {
    by_joint.chain.OrderJointValuesBy(names);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "the joint names differ: the model's 'irb1600::joint7' not in the scene; the "
              "scene's 'irb1600::joint1' not in the model");
  }
}

// A URDF's free base, as the server reads it: a 'floating' joint from the world (its child's
// pose the joint's seven values, starting at its <origin>), or --floating-base (the root
// moved by a free joint named after it, frame 0 the world).
TEST(WorldScene, AUrdfsFloatingJointAndFloatingBaseAreFreeJoints) {
  const std::string trunk =
      "  <link name=\"trunk\"><visual><geometry><box size=\"0.4 0.2 0.1\"/></geometry></visual>"
      "</link>\n  <link name=\"leg\"/>\n"
      "  <joint name=\"hip\" type=\"revolute\"><parent link=\"trunk\"/><child link=\"leg\"/>"
      "<axis xyz=\"0 1 0\"/></joint>\n</robot>\n";
  const MeshFinder none = [](const std::string&) { return std::filesystem::path(); };
  const SceneDescription floating = SceneFromModelText(
      "<robot name=\"walker\">\n  <link name=\"world\"/>\n"
      "  <joint name=\"base_free\" type=\"floating\"><parent link=\"world\"/>"
      "<child link=\"trunk\"/><origin xyz=\"0 0 1\" rpy=\"0 0 1.5707963267948966\"/></joint>\n" +
          trunk,
      "walker.urdf", none);
  ASSERT_EQ(floating.chain.dof(), 7 + 1);
  EXPECT_EQ(floating.chain.dof_joint(0).kind, ChainJointKind::kFree);
  EXPECT_EQ(floating.chain.dof_joint(0).name, "base_free");
  const std::vector<double> start = {0, 0, 1, std::sqrt(0.5), 0, 0, std::sqrt(0.5), 0};
  for (int k = 0; k < 8; ++k) EXPECT_NEAR(floating.initial_q[k], start[k], 1e-12) << k;
  std::vector<Eigen::Isometry3d> frames(floating.chain.frame_count());
  floating.chain.Compute(floating.initial_q, frames);
  EXPECT_LT((frames[1].translation() - Vector3d(0, 0, 1)).norm(), 1e-12);
  EXPECT_LT((frames[1].linear() * Vector3d::UnitX() - Vector3d::UnitY()).norm(), 1e-12);

  const SceneDescription base =
      SceneFromModelText("<robot name=\"walker\">\n" + trunk, "walker.urdf", none, true);
  EXPECT_EQ(base.frame_names[0], "world");
  EXPECT_EQ(base.frame_names[1], "trunk");
  EXPECT_EQ(base.chain.dof_joint(0).name, "trunk");
  EXPECT_EQ(base.chain.dof(), 7 + 1);
  EXPECT_EQ(base.visuals.at(0).frame, 1);  // the trunk's box moves with it
}

SceneOptions Offscreen() {
  SceneOptions options;
  options.width = 640;
  options.height = 480;
  options.offscreen = true;
  return options;
}

TEST(WorldScene, AFreeBoxFollowsItsPositionAndQuaternionAndTheSnapshotShowsEveryModel) {
  const SceneDescription description = SceneFromModelFile(kWorld);
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  Scene scene(description, Offscreen());
  ASSERT_EQ(scene.part_actor_count(), 15);
  std::vector<double> q = description.initial_q;
  scene.SetJointValues(q);
  scene.SyncActors();
  std::map<std::string, int> actor_of;  // the first actor of each model
  for (size_t k = 0; k < description.visuals.size(); ++k) {
    actor_of.emplace(ModelOf(description.visuals[k].name), static_cast<int>(k));
  }
  vtkActor* box_a = scene.part_actors()[actor_of.at("box_a")];
  EXPECT_LT((WorldBounds(box_a).center() - Vector3d(1.0, -0.15, 0.9)).norm(), 1e-9);
  EXPECT_NEAR(WorldBounds(box_a).sizes().x(), 0.1, 1e-9);
  // Half a metre lower and turned an eighth of a turn about z (quaternion not normalised:
  // the chain normalises it): the cube's bounds widen to 0.1 * sqrt(2).
  const double half = M_PI / 8;
  const std::vector<double> moved = {1.0, -0.15, 0.4, 2 * std::cos(half), 0, 0, 2 * std::sin(half)};
  std::copy(moved.begin(), moved.end(), q.begin() + 6);
  scene.SetJointValues(q);
  scene.SyncActors();
  EXPECT_LT((WorldBounds(box_a).center() - Vector3d(1.0, -0.15, 0.4)).norm(), 1e-9);
  EXPECT_NEAR(WorldBounds(box_a).sizes().x(), 0.1 * std::sqrt(2.0), 1e-9);
  // The table stands where the world puts it, whatever the joints do.
  const Eigen::AlignedBox3d top = WorldBounds(scene.part_actors()[actor_of.at("table")]);
  EXPECT_LT((top.center() - Vector3d(1.1, 0, 0.7)).norm(), 1e-9);

  // The snapshot: each model's colour is in the picture (the boxes' blue, the table's
  // brown, the robot's orange).
  std::vector<vtkActor*> actors;
  vtkActorCollection* collection = scene.renderer()->GetActors();
  collection->InitTraversal();
  while (vtkActor* actor = collection->GetNextActor()) actors.push_back(actor);
  for (vtkActor* actor : actors) actor->VisibilityOff();
  const RgbImage background = scene.Capture();
  for (vtkActor* actor : actors) actor->VisibilityOn();
  const RgbImage image = scene.Capture();
  int changed = 0, blue = 0, brown = 0, orange = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      int d = 0;
      for (int c = 0; c < 3; ++c) {
        d = std::max(d, std::abs(int(image.At(x, y)[c]) - int(background.At(x, y)[c])));
      }
      if (d <= 12) continue;
      ++changed;
      const int r = image.At(x, y)[0], g = image.At(x, y)[1], b = image.At(x, y)[2];
      if (b > r + 40 && b > g + 10) ++blue;
      if (r > b + 30 && g > b + 15 && r < g + 60) ++brown;
      if (r > g + 60 && g > b + 15) ++orange;
    }
  }
  EXPECT_GT(changed, image.width * image.height / 50) << "the snapshot is nearly blank";
  EXPECT_GT(blue, 20) << "no box in the picture";
  EXPECT_GT(brown, 20) << "no table in the picture";
  EXPECT_GT(orange, 20) << "no robot in the picture";
}

// A comparison of two runs of the world (a replay's --compare): the ghost, a second copy of
// every model, takes its own run's values and poses each free box from them, bit for bit as
// the chain computes them, while the scene keeps its run's pose.
TEST(WorldScene, TheGhostOfAWorldRunPosesItsOwnFreeBoxes) {
  const SceneDescription description = SceneFromModelFile(kWorld);
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  SceneOptions options = Offscreen();
  options.ghost_opacity = 0.35;
  Scene scene(description, options);
  GhostLayer* ghost = scene.ghost();
  ASSERT_NE(ghost, nullptr);
  EXPECT_EQ(ghost->actor_count(), scene.part_actor_count());
  const std::vector<double> q = description.initial_q;
  std::vector<double> ghost_q = q;
  const double half = M_PI / 8;  // box_a half a metre lower, turned an eighth of a turn about z
  const std::vector<double> moved = {1.0, -0.15, 0.4, std::cos(half), 0, 0, std::sin(half)};
  std::copy(moved.begin(), moved.end(), ghost_q.begin() + 6);
  scene.SetJointValues(q);
  ghost->SetJointValues(ghost_q);

  PoseSolver solver(description.chain, description.probes);
  Pose own = solver.MakePose(), theirs = solver.MakePose();
  solver.Solve(q, &own);
  solver.Solve(ghost_q, &theirs);
  std::vector<Eigen::Isometry3d> scene_frames;
  scene.Frames(&scene_frames);
  const std::vector<Eigen::Isometry3d> ghost_frames = ghost->Frames();
  ASSERT_EQ(ghost_frames.size(), theirs.frames.size());
  ASSERT_EQ(scene_frames.size(), own.frames.size());
  int differ = 0;
  for (size_t k = 0; k < ghost_frames.size(); ++k) {
    EXPECT_TRUE(ghost_frames[k].isApprox(theirs.frames[k], 0.0)) << "frame " << k;
    EXPECT_TRUE(scene_frames[k].isApprox(own.frames[k], 0.0)) << "frame " << k;
    if (ghost_frames[k].isApprox(scene_frames[k], 0.0)) continue;
    if (differ++ == 0) {  // box_a's link: where the ghost's values put it
      EXPECT_LT((ghost_frames[k].translation() - Vector3d(1.0, -0.15, 0.4)).norm(), 1e-15);
      EXPECT_LT((Eigen::Quaterniond(ghost_frames[k].rotation()).coeffs() -
                 Eigen::Quaterniond(std::cos(half), 0, 0, std::sin(half)).coeffs())
                    .norm(),
                1e-15);
    }
  }
  EXPECT_GE(differ, 1);  // box_a's frames, and nothing else of the world
  EXPECT_LT(differ, static_cast<int>(ghost_frames.size()) / 2);
  scene.Render();  // both drawn
}

}  // namespace
}  // namespace mbstream::viewer
