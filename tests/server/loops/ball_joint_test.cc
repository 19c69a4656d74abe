// A ball joint inside the tree (server/model/ball_joint.h): three revolute joints through its
// centre, Cardan angles x-y-z named JOINT.x, JOINT.y, JOINT.z. A spherical pendulum (a rigid
// body of general inertia on a ball joint) released under gravity conserves its energy and
// follows Simbody's Ball mobilizer (quaternions) to 1e-7; a motion through the Cardan angles'
// singularity stops the run, naming the joint, the angle and the time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "server/engine/engine.h"
#include "server/parse/sdf_import.h"
#include "tests/server/loops/simbody_linkage.h"

namespace mbstream {
namespace {

// The pivot 1 m up, the joint frame turned 0.3 rad about x; the body's centre of mass 0.52 m
// from the pivot, off its axes, with three different principal moments.
constexpr char kPendulum[] = R"(<?xml version="1.0"?>
<sdf version="1.7">
  <model name="spherical_pendulum">
    <link name="bob">
      <pose>0 0 1 0.3 0 0</pose>
      <inertial>
        <pose>0.1 0.05 -0.5 0 0 0</pose>
        <mass>1.5</mass>
        <inertia><ixx>0.02</ixx><iyy>0.03</iyy><izz>0.04</izz>
          <ixy>0.001</ixy><ixz>0</ixz><iyz>0</iyz></inertia>
      </inertial>
    </link>
    <joint name="ball" type="ball">
      <parent>world</parent>
      <child>bob</child>
    </joint>
  </model>
</sdf>
)";

Matrix3d Cardan(double x, double y, double z) {
  return (Eigen::AngleAxisd(x, Vector3d::UnitX()) * Eigen::AngleAxisd(y, Vector3d::UnitY()) *
          Eigen::AngleAxisd(z, Vector3d::UnitZ()))
      .toRotationMatrix();
}

// The angular velocity (in the joint frame) of Cardan rates qd at angles q.
Vector3d CardanRate(const Eigen::Vector3d& q, const Eigen::Vector3d& qd) {
  const Matrix3d Rx = Eigen::AngleAxisd(q(0), Vector3d::UnitX()).toRotationMatrix();
  const Matrix3d Ry = Eigen::AngleAxisd(q(1), Vector3d::UnitY()).toRotationMatrix();
  return Vector3d::UnitX() * qd(0) + Rx * Vector3d::UnitY() * qd(1) +
         Rx * Ry * Vector3d::UnitZ() * qd(2);
}

RunConfig PassiveConfig(const Eigen::Vector3d& q0, const Eigen::Vector3d& qd0) {
  RunConfig config;
  config.duration = 2.0;
  config.output_interval = 0.01;
  config.formulation = Formulation::kJoint;
  config.method = Method::kAdams;
  config.rtol = 1e-12;
  config.atol = 1e-14;
  config.drives.assign(3, DriveConfig{});
  config.q0 = q0;
  config.qd0 = qd0;
  return config;
}

TEST(BallJointTest, ABallJointInTheTreeIsThreeNamedRevoluteAxesThroughItsCentre) {
  const SdfImport sdf = ImportSdf(kPendulum, "pendulum.sdf");
  const Model& model = sdf.model;
  ASSERT_EQ(model.num_dofs(), 3);
  ASSERT_EQ(model.ball_joints.size(), 1u);
  EXPECT_EQ(model.ball_joints[0].name, "ball");
  EXPECT_EQ(model.ball_joints[0].where, "pendulum.sdf:13");
  const char* names[] = {"ball.x", "ball.y", "ball.z"};
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(model.bodies[k].joint.name, names[k]);
    EXPECT_EQ(model.bodies[k].joint.type, JointType::kRevolute);
    EXPECT_EQ(model.bodies[k].joint.axis, Vector3d::Unit(k));
    EXPECT_EQ(model.bodies[k].inertia.mass, k == 2 ? 1.5 : 0.0);
  }
  EXPECT_EQ(model.bodies[2].name, "bob");
  EXPECT_NEAR(model.bodies[0].joint.X_PJ.p.z(), 1.0, 1e-15);
  EXPECT_TRUE(model.bodies[1].joint.X_PJ.p.isZero() && model.bodies[2].joint.X_PJ.p.isZero());
}

// Measured (2026-11-27): Adams at rtol 1e-12: the orientation differs from Simbody's by
// 1e-9 at most over 2 s; the energy drifts by 1e-11 of its scale.
TEST(BallJointTest, ASphericalPendulumConservesEnergyAndFollowsSimbodysBallMobilizer) {
  const SdfImport sdf = ImportSdf(kPendulum, "pendulum.sdf");
  const Eigen::Vector3d q0(0.6, 0.2, 0.1), qd0(0.3, 2.0, -0.5);
  const RunResult ours = Simulate(sdf.model, sdf.loops, PassiveConfig(q0, qd0));
  ASSERT_EQ(ours.stats.status, RunStatus::kFinished) << ours.stats.message;
  EXPECT_EQ(ours.joint_names, (std::vector<std::string>{"ball.x", "ball.y", "ball.z"}));

  const std::vector<Matrix3d> theirs =
      SimbodyBallOrientations(sdf.model, Cardan(q0(0), q0(1), q0(2)), CardanRate(q0, qd0), ours.t);
  double worst = 0.0, turned = 0.0;
  for (int k = 0; k < ours.num_frames(); ++k) {
    const double* q = &ours.q[3 * k];
    const Matrix3d R = Cardan(q[0], q[1], q[2]);
    worst = std::max(worst, (R - theirs[k]).cwiseAbs().maxCoeff());
    turned = std::max(turned, (theirs[k] - theirs[0]).cwiseAbs().maxCoeff());
  }
  EXPECT_GT(turned, 0.5);  // it swung
  EXPECT_LT(worst, 1e-7);

  ASSERT_TRUE(ours.has_energy);
  const double e0 = ours.kinetic[0] + ours.potential[0];
  double drift = 0.0, scale = 0.0;
  for (int k = 0; k < ours.num_frames(); ++k) {
    drift = std::max(drift, std::abs(ours.kinetic[k] + ours.potential[k] - e0));
    scale = std::max(scale, ours.kinetic[k]);
  }
  EXPECT_LT(drift, 1e-9 * scale);
  std::printf("orientation vs Simbody %.3g, energy drift %.3g J of %.3g J\n", worst, drift, scale);
}

// A bob whose centre of mass is on the joint frame's -z axis, swung about y from 69 degrees:
// the motion stays in the x-z plane and goes straight through ball.y = 90 degrees, where the
// Cardan angles lock. The run stops there and says which joint, where and when.
TEST(BallJointTest, AMotionThroughTheGimbalLockStopsTheRunNamingTheJoint) {
  std::string text = kPendulum;
  text.replace(text.find("0 0 1 0.3 0 0"), 13, "0 0 1 0 0 0");
  text.replace(text.find("0.1 0.05 -0.5 0 0 0"), 19, "0 0 -0.5 0 0 0");
  text.replace(text.find("<ixy>0.001</ixy>"), 16, "<ixy>0</ixy>");
  const SdfImport sdf = ImportSdf(text, "pendulum.sdf");
  const RunResult result =
      Simulate(sdf.model, sdf.loops, PassiveConfig({0.0, 1.2, 0.0}, {0.0, 6.0, 0.0}));
  EXPECT_EQ(result.stats.status, RunStatus::kFailed);
  EXPECT_NE(
      result.stats.message.find("ball joint 'ball' (pendulum.sdf:13) reached its gimbal lock"),
      std::string::npos)
      << result.stats.message;
  EXPECT_NE(result.stats.message.find("ball.y ="), std::string::npos) << result.stats.message;
  EXPECT_LT(result.stats.t_reached, 0.2);
  std::printf("%s\n", result.stats.message.c_str());
}

// The general bob swung about y from 69 degrees passes beside the lock (it is a curve among
// the orientations: ball.y comes within 1.4 degrees of 90 while ball.x and ball.z swing by 180
// degrees in 0.05 s): the run goes on, its energy kept, and warns how close it came.
TEST(BallJointTest, AMotionBesideTheGimbalLockIsFollowedAndWarned) {
  const SdfImport sdf = ImportSdf(kPendulum, "pendulum.sdf");
  const RunResult result =
      Simulate(sdf.model, sdf.loops, PassiveConfig({0.0, 1.2, 0.0}, {0.0, 6.0, 0.0}));
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_LT(result.stats.energy_error_max, 1e-9);
  bool warned = false;
  for (const std::string& warning : result.stats.warnings) {
    if (warning.find("ball joint 'ball' (pendulum.sdf:13) came within") != std::string::npos) {
      warned = true;
      std::printf("%s\n", warning.c_str());
    }
  }
  EXPECT_TRUE(warned);
}

// The Delta with its wrist (rod 1a to the platform) a ball joint in the tree
// (tests/data/delta_ball.sdf, written by models/linkages/generate.py) moves as the shipped
// Delta, whose wrist is three revolutes: wrist.x = -wrist_1, wrist.y = wrist_2, wrist.z =
// wrist_3 and every other joint the same, released under gravity (ODE with projection).
TEST(BallJointTest, TheDeltaWithABallJointWristMovesAsWithThreeRevolutes) {
  const SdfImport ball =
      ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/delta_ball.sdf");
  const SdfImport revolutes =
      ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/delta.sdf");
  ASSERT_EQ(ball.model.num_dofs(), revolutes.model.num_dofs());
  ASSERT_EQ(ball.model.ball_joints.size(), 1u);
  // The shipped Delta's wrist has two small links between its revolutes (5 g, 1e-7 kg*m^2
  // about their origin, the joint centre); the ball's axes carry them here, so that both
  // describe the same bodies.
  Model model = ball.model;
  for (int k = 0; k < 2; ++k) {
    const RigidInertia& small =
        revolutes.model.bodies[revolutes.model.FindBody(k == 0 ? "wrist1" : "wrist2")].inertia;
    model.bodies[model.ball_joints[0].first_body + k].inertia = small;
  }
  RunConfig config;  // models/linkages/delta-passive.json, before the fall's singularity
  config.duration = 0.2;
  config.output_interval = 0.01;
  config.rtol = 1e-10;
  config.atol = 1e-12;
  config.formulation = Formulation::kJoint;
  config.drives.assign(static_cast<size_t>(ball.model.num_dofs()), DriveConfig{});
  const RunResult a = Simulate(model, ball.loops, config);
  const RunResult b = Simulate(revolutes.model, revolutes.loops, config);
  ASSERT_EQ(a.stats.status, RunStatus::kFinished) << a.stats.message;
  ASSERT_EQ(b.stats.status, RunStatus::kFinished) << b.stats.message;
  ASSERT_EQ(a.num_frames(), b.num_frames());
  const std::map<std::string, std::pair<std::string, double>> renamed = {
      {"wrist.x", {"wrist_1", -1.0}}, {"wrist.y", {"wrist_2", 1.0}}, {"wrist.z", {"wrist_3", 1.0}}};
  double worst = 0.0, travel = 0.0;
  for (int j = 0; j < ball.model.num_dofs(); ++j) {
    const std::string& name = a.joint_names[j];
    const auto it = renamed.find(name);
    const std::string other = it == renamed.end() ? name : it->second.first;
    const double sign = it == renamed.end() ? 1.0 : it->second.second;
    const auto at = std::find(b.joint_names.begin(), b.joint_names.end(), other);
    ASSERT_NE(at, b.joint_names.end()) << name;
    const long k = at - b.joint_names.begin();
    for (int f = 0; f < a.num_frames(); ++f) {
      const double qa = a.q[f * a.num_dofs + j], qb = sign * b.q[f * b.num_dofs + k];
      worst = std::max(worst, std::abs(qa - qb));
      travel = std::max(travel, std::abs(qb - sign * b.q[k]));
    }
  }
  std::printf("Delta, ball wrist against three revolutes: %.3g rad (travel %.3g rad)\n", worst,
              travel);
  EXPECT_GT(travel, 0.05);
  EXPECT_LT(worst, 1e-7);
}

}  // namespace
}  // namespace mbstream
