// The viewer's probe equals an independent forward kinematics of the seed's chain.
#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "shared/common/check.h"
#include "tests/viewer/script_test_util.h"
#include "viewer/kinematics/pose_solver.h"
#include "viewer/model/script_scene.h"
#include "viewer/model/urdf_scene.h"

namespace mbstream::viewer {
namespace {

using Eigen::AngleAxisd;
using Eigen::Isometry3d;
using Eigen::Translation3d;
using Eigen::Vector3d;
using scene_script::testing::kSeedDevice;
using scene_script::testing::SourcePath;

constexpr double kPi = std::numbers::pi;

// The seed's IRB 1600 (the Device block of models/irb1600/irb1600.scene), written out
// independently: frames of joints 1..6 and the TCP.
std::vector<Isometry3d> SeedFrames(const std::vector<double>& q) {
  std::vector<Isometry3d> f(7);
  f[0] = Isometry3d::Identity();
  f[1] = f[0] * AngleAxisd(q[0], Vector3d::UnitZ());
  f[2] = f[1] * Translation3d(0.150, 0, 0.4865) * AngleAxisd(q[1], Vector3d::UnitY());
  f[3] = f[2] * Translation3d(0, 0, 0.475) * AngleAxisd(q[2], Vector3d::UnitY());
  f[4] = f[3] * Translation3d(0.600, 0, 0) * AngleAxisd(q[3], Vector3d::UnitX());
  f[5] = f[4] * AngleAxisd(q[4], Vector3d::UnitY());
  f[6] = f[5] * AngleAxisd(q[5], Vector3d::UnitX());
  return f;
}

Vector3d SeedTcp(const std::vector<double>& q) { return SeedFrames(q)[6] * Vector3d(0.065, 0, 0); }

// The seed's Device placement: Rz(-90) Ry(-90) Rz(0).
Isometry3d SeedBaseInWorld() {
  return Isometry3d(AngleAxisd(-kPi / 2, Vector3d::UnitZ()) *
                    AngleAxisd(-kPi / 2, Vector3d::UnitY()));
}

std::vector<std::vector<double>> RandomPoses(int count) {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> angle(-2 * kPi, 2 * kPi);
  std::vector<std::vector<double>> poses{std::vector<double>(6, 0.0),
                                         {kPi, kPi / 3, kPi / 4, kPi, 0.6 * kPi, kPi}};
  while (static_cast<int>(poses.size()) < count) {
    std::vector<double> q(6);
    for (double& v : q) v = angle(rng);
    poses.push_back(q);
  }
  return poses;
}

SceneDescription SceneOf(const std::string& text) {
  const scene_script::Translation translation = scene_script::TranslateScript(text);
  EXPECT_TRUE(translation.ok()) << scene_script::testing::ErrorsOf(translation).front();
  return SceneFromScript(translation.script);
}

PoseSolver SolverOf(const SceneDescription& scene) { return PoseSolver(scene.chain, scene.probes); }

TEST(ProbeKinematics, TheSeedSamplePoints) {
  const PoseSolver solver =
      SolverOf(SceneOf(std::string(kSeedDevice) + "Probe P IRB1600#6 (shift x 65) refer IRB1600;"));
  Pose pose = solver.MakePose();
  EXPECT_LT((pose.probes[0] - Vector3d(0.815, 0, 0.9615)).norm(), 1e-12);
  const std::vector<double> q{kPi, kPi / 3, kPi / 4, kPi, 0.6 * kPi, kPi};
  solver.Solve(q, &pose);
  EXPECT_LT((pose.probes[0] - Vector3d(-0.470981559, 0, 0.147846341)).norm(), 1e-9);
}

TEST(ProbeKinematics, ProbeInTheBaseEqualsIndependentForwardKinematicsOverManyPoses) {
  const PoseSolver solver = SolverOf(
      SceneOf(std::string(kSeedDevice) + "Probe P IRB1600#6 (shift x 65) refer IRB1600;\n"
                                         "Probe W IRB1600#6 (shift x 65) refer World;\n"
                                         "Probe L IRB1600#6 (x 65) refer IRB1600#3;\n"
                                         "Probe Fixed World (x 100 y 200 z 300) refer IRB1600#2;"));
  Pose pose = solver.MakePose();
  double worst = 0;
  for (const std::vector<double>& q : RandomPoses(2000)) {
    solver.Solve(q, &pose);
    const std::vector<Isometry3d> f = SeedFrames(q);
    const Vector3d tcp = SeedTcp(q);
    const Vector3d world = SeedBaseInWorld() * tcp;
    const Vector3d in_link3 = f[3].inverse() * tcp;
    const Vector3d fixed_in_link2 = (SeedBaseInWorld() * f[2]).inverse() * Vector3d(0.1, 0.2, 0.3);
    worst =
        std::max({worst, (pose.probes[0] - tcp).norm(), (pose.probes[1] - world).norm(),
                  (pose.probes[2] - in_link3).norm(), (pose.probes[3] - fixed_in_link2).norm()});
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(solver.probes()[1].refer_name, "World");
  EXPECT_EQ(solver.probes()[2].refer_name, "IRB1600#3");
}

TEST(ProbeKinematics, ShippedSceneMatchesTheUrdfChainAndTheSeed) {
  const SceneDescription script =
      SceneOf(scene_script::testing::ReadFile(SourcePath("models/irb1600/irb1600.scene")));
  const SceneDescription urdf = SceneFromUrdfFile(SourcePath("models/irb1600/irb1600.urdf"));
  ASSERT_EQ(script.chain.dof(), 6);
  ASSERT_EQ(urdf.chain.dof(), 6);
  ASSERT_EQ(urdf.probes.size(), 1u);
  ASSERT_EQ(script.probes.size(), 1u);
  EXPECT_EQ(script.probes[0].refer_name, "IRB1600");
  EXPECT_EQ(urdf.probes[0].refer_name, "base_link");
  const PoseSolver from_script = SolverOf(script);
  const PoseSolver from_urdf = SolverOf(urdf);
  Pose a = from_script.MakePose();
  Pose b = from_urdf.MakePose();
  double worst = 0;
  for (const std::vector<double>& q : RandomPoses(500)) {
    from_script.Solve(q, &a);
    from_urdf.Solve(q, &b);
    worst =
        std::max({worst, (a.probes[0] - b.probes[0]).norm(), (a.probes[0] - SeedTcp(q)).norm()});
    // Every link frame relative to the base agrees (the URDF has one more: the tcp link).
    for (int k = 1; k <= 6; ++k) {
      const Isometry3d script_k = a.frames[0].inverse() * a.frames[k];
      const Isometry3d urdf_k = b.frames[0].inverse() * b.frames[k];
      worst = std::max(worst, (script_k.matrix() - urdf_k.matrix()).norm());
    }
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(ProbeKinematics, PrismaticJointsBranchesAndPostTransforms) {
  const SceneDescription scene = SceneOf(R"(
    Device G (shift x 1000 euler 0 0 90)
      Joint 1 prismatic x (shift z 50)
      Joint 2 (euler 0 90 0) revolute y
      Extend 1
      Joint 3 (x-150) revolute z (shift y 70 euler 0 0 45)
      Tcp (shift x 10);
    Probe A G#2 (x 20 y 30 z 40) refer G;
    Probe B G#3 (x 5) refer World;)");
  ASSERT_EQ(scene.chain.dof(), 3);
  EXPECT_EQ(scene.chain.joints()[2].parent, 1);
  const PoseSolver solver = SolverOf(scene);
  Pose pose = solver.MakePose();
  const double d = kPi / 180;
  const std::vector<double> q{0.25, 0.7, -1.1};
  solver.Solve(q, &pose);
  const Isometry3d f1 = Isometry3d(Translation3d(q[0], 0, 0)) * Translation3d(0, 0, 0.05);
  const Isometry3d f2 =
      f1 * AngleAxisd(90 * d, Vector3d::UnitY()) * AngleAxisd(q[1], Vector3d::UnitY());
  const Isometry3d f3 = f1 * Translation3d(-0.15, 0, 0) * AngleAxisd(q[2], Vector3d::UnitZ()) *
                        Translation3d(0, 0.07, 0) * AngleAxisd(45 * d, Vector3d::UnitZ());
  const Isometry3d base = Translation3d(1, 0, 0) * AngleAxisd(90 * d, Vector3d::UnitZ());
  EXPECT_LT((pose.probes[0] - f2 * Vector3d(0.02, 0.03, 0.04)).norm(), 1e-12);
  EXPECT_LT((pose.probes[1] - base * f3 * Vector3d(0.005, 0, 0)).norm(), 1e-12);
  EXPECT_LT((pose.probes_world[0] - base * f2 * Vector3d(0.02, 0.03, 0.04)).norm(), 1e-12);
}

TEST(ProbeKinematics, JointCountMismatchNamesBothCounts) {
  const PoseSolver solver = SolverOf(SceneOf(kSeedDevice));
  Pose pose = solver.MakePose();
  const std::vector<double> q(7, 0.0);
  try {
    solver.Solve(q, &pose);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "the scene has 6 joints but 7 joint values were given");
  }
}

TEST(ProbeKinematics, ScriptUnitsToSi) {
  const SceneDescription scene =
      SceneOf("Device D Joint 1 revolute z Joint 2 prismatic x Initial (90 250);");
  const std::vector<double> si = ScriptUnitsToSi(scene.chain, std::vector<double>{180, 1500});
  EXPECT_DOUBLE_EQ(si[0], kPi);
  EXPECT_DOUBLE_EQ(si[1], 1.5);
  EXPECT_DOUBLE_EQ(scene.initial_q[0], kPi / 2);
  EXPECT_DOUBLE_EQ(scene.initial_q[1], 0.25);
  EXPECT_THROW(ScriptUnitsToSi(scene.chain, std::vector<double>{1}), InputError);
}

TEST(UrdfScene, VisualsFramesAndErrors) {
  const SceneDescription urdf = SceneFromUrdfFile(SourcePath("models/irb1600/irb1600.urdf"));
  EXPECT_EQ(urdf.title, "irb1600");
  EXPECT_EQ(urdf.frame_names.front(), "base_link");
  EXPECT_EQ(urdf.frame_names.back(), "tcp");
  EXPECT_EQ(urdf.visuals.size(), 7u);  // base box, 6 link shapes
  EXPECT_EQ(urdf.chain.frame_count(), 8);
  EXPECT_THROW(SceneFromUrdfFile("/nonexistent.urdf"), InputError);
  // A mesh that is not there: a labelled placeholder box of the link's inertia, and a
  // warning (the server accepts such a model; the physics needs no mesh).
  const SceneDescription missing = SceneFromUrdf(R"(<robot name="r"><link name="a">
      <inertial><origin xyz="0 0 0.5"/><mass value="12"/>
        <inertia ixx="0.5" iyy="0.26" izz="0.26" ixy="0" ixz="0" iyz="0"/></inertial>
      <visual><geometry><mesh filename="package://r/meshes/a.dae"/></geometry></visual>
      </link></robot>)",
                                                 "r.urdf", "/nonexistent");
  ASSERT_EQ(missing.visuals.size(), 1u);
  EXPECT_TRUE(missing.visuals[0].placeholder);
  EXPECT_EQ(missing.visuals[0].mesh_filename, "package://r/meshes/a.dae");
  ASSERT_EQ(missing.warnings.size(), 1u);
  EXPECT_EQ(missing.warnings[0],
            "r.urdf: link 'a': mesh 'package://r/meshes/a.dae' is not in the model's files; "
            "drawn as a box of the link's inertia (submit the model with its meshes)");
  ASSERT_TRUE(std::holds_alternative<Mesh>(missing.visuals[0].geometry));
  Eigen::AlignedBox3d box;
  for (const Vector3d& p : std::get<Mesh>(missing.visuals[0].geometry).points) {
    box.extend(missing.visuals[0].placement * p);
  }
  // 12 kg with moments 0.5, 0.26, 0.26: a box 0.1 x 0.5 x 0.5 m about (0, 0, 0.5).
  EXPECT_TRUE(box.sizes().isApprox(Vector3d(0.1, 0.5, 0.5), 1e-9)) << box.sizes().transpose();
  EXPECT_TRUE(box.center().isApprox(Vector3d(0, 0, 0.5), 1e-9)) << box.center().transpose();
  EXPECT_THROW(SceneFromUrdf("<robot", "bad.urdf", "/tmp"), InputError);
}

}  // namespace
}  // namespace mbstream::viewer
