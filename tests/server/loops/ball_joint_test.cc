// A ball joint inside the tree (JointType::kBall): one body, its rotation a unit quaternion
// JOINT.qw .qx .qy .qz relative to the joint frame, its angular velocity JOINT.wx .wy .wz in the
// child's frame. A spherical pendulum (a rigid body of general inertia on a ball joint)
// released under gravity conserves its energy and follows Simbody's Ball mobilizer to 1e-7; a
// swing through the former Cardan expansion's gimbal lock (q_y = 90 degrees) follows a
// revolute pendulum; a closed loop with a ball joint in its spanning tree runs (method bdf), and
// method ida refuses it, naming it.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "server/engine/engine.h"
#include "server/parse/sdf_import.h"
#include "server/sim/loop_run.h"
#include "server/sim/run_trust.h"
#include "shared/common/check.h"
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

Matrix3d RotationOf(const double* quat) {
  return Eigen::Quaterniond(quat[0], quat[1], quat[2], quat[3]).normalized().toRotationMatrix();
}

RunConfig PassiveConfig(const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0) {
  RunConfig config;
  config.duration = 2.0;
  config.output_interval = 0.01;
  config.formulation = Formulation::kJoint;
  config.method = Method::kAdams;
  config.rtol = 1e-12;
  config.atol = 1e-14;
  config.drives.assign(static_cast<size_t>(qd0.size()), DriveConfig{});
  config.q0 = q0;
  config.qd0 = qd0;
  return config;
}

// The quaternion (qw qx qy qz) of R.
Eigen::VectorXd QuaternionOf(const Matrix3d& R) {
  const Eigen::Quaterniond quat(R);
  Eigen::VectorXd q(4);
  q << quat.w(), quat.x(), quat.y(), quat.z();
  return q;
}

TEST(BallJointTest, ABallJointInTheTreeIsOneBodyWithAQuaternion) {
  const SdfImport sdf = ImportSdf(kPendulum, "pendulum.sdf");
  const Model& model = sdf.model;
  ASSERT_EQ(model.num_bodies(), 1);
  EXPECT_EQ(model.nq(), 4);
  EXPECT_EQ(model.nv(), 3);
  EXPECT_EQ(model.ball_bodies, std::vector<int>{0});
  EXPECT_EQ(model.quaternions, std::vector<int>{0});
  const Body& body = model.bodies[0];
  EXPECT_EQ(body.joint.name, "ball");
  EXPECT_EQ(body.joint.type, JointType::kBall);
  EXPECT_EQ(body.name, "bob");
  EXPECT_EQ(body.inertia.mass, 1.5);
  EXPECT_NEAR(body.joint.X_PJ.p.z(), 1.0, 1e-15);
}

// Measured (2026-12-02): Adams at rtol 1e-12: the orientation differs from Simbody's by
// 1e-9 at most over 2 s; the energy drifts by 1e-11 of its scale; the frames' quaternions are
// unit to 2.2e-16.
TEST(BallJointTest, ASphericalPendulumConservesEnergyAndFollowsSimbodysBallMobilizer) {
  const SdfImport sdf = ImportSdf(kPendulum, "pendulum.sdf");
  const Matrix3d R0 = Cardan(0.6, 0.2, 0.1);
  const Vector3d w_F(0.3, 2.0, -0.5);  // in the joint frame
  const Eigen::VectorXd q0 = QuaternionOf(R0);
  const Eigen::VectorXd qd0 = R0.transpose() * w_F;  // in the bob's frame
  const RunResult ours = Simulate(sdf.model, sdf.loops, PassiveConfig(q0, qd0));
  ASSERT_EQ(ours.stats.status, RunStatus::kFinished) << ours.stats.message;
  EXPECT_EQ(ours.joint_names, (std::vector<std::string>{"ball.wx", "ball.wy", "ball.wz"}));
  EXPECT_EQ(ours.position_names,
            (std::vector<std::string>{"ball.qw", "ball.qx", "ball.qy", "ball.qz"}));
  ASSERT_EQ(ours.positions(), 4);

  const std::vector<Matrix3d> theirs = SimbodyBallOrientations(sdf.model, R0, w_F, ours.t);
  double worst = 0.0, turned = 0.0, norm = 0.0;
  for (int k = 0; k < ours.num_frames(); ++k) {
    const double* q = &ours.q[4 * k];
    norm = std::max(norm, std::abs(Eigen::Vector4d(q[0], q[1], q[2], q[3]).norm() - 1.0));
    worst = std::max(worst, (RotationOf(q) - theirs[k]).cwiseAbs().maxCoeff());
    turned = std::max(turned, (theirs[k] - theirs[0]).cwiseAbs().maxCoeff());
  }
  EXPECT_GT(turned, 0.5);  // it swung
  EXPECT_LT(worst, 1e-7);
  EXPECT_LT(norm, 1e-12);

  ASSERT_TRUE(ours.has_energy);
  const double e0 = ours.kinetic[0] + ours.potential[0];
  double drift = 0.0, scale = 0.0;
  for (int k = 0; k < ours.num_frames(); ++k) {
    drift = std::max(drift, std::abs(ours.kinetic[k] + ours.potential[k] - e0));
    scale = std::max(scale, ours.kinetic[k]);
  }
  EXPECT_LT(drift, 1e-9 * scale);
  std::printf(
      "orientation vs Simbody %.3g, energy drift %.3g J of %.3g J, frames' | |quat| - 1 | "
      "%.3g\n",
      worst, drift, scale, norm);
}

// A bob whose centre of mass is on the joint frame's -z axis, swung about y from 69 degrees at
// 6 rad/s: the motion stays in the x-z plane and goes straight through 90 degrees about y,
// where the Cardan expansion of the ball joint locked. It follows a revolute pendulum about y
// (the same file with the joint made revolute): quat = (cos a/2, 0, sin a/2, 0), w = (0, a', 0).
TEST(BallJointTest, ASwingThroughTheFormerGimbalLockFollowsARevolutePendulum) {
  std::string text = kPendulum;
  text.replace(text.find("0 0 1 0.3 0 0"), 13, "0 0 1 0 0 0");
  text.replace(text.find("0.1 0.05 -0.5 0 0 0"), 19, "0 0 -0.5 0 0 0");
  text.replace(text.find("<ixy>0.001</ixy>"), 16, "<ixy>0</ixy>");
  std::string revolute_text = text;
  revolute_text.replace(revolute_text.find("type=\"ball\">"), 13,
                        "type=\"revolute\"><axis><xyz>0 1 0</xyz></axis>");
  const SdfImport ball = ImportSdf(text, "pendulum.sdf");
  const SdfImport revolute = ImportSdf(revolute_text, "revolute.sdf");
  ASSERT_EQ(revolute.model.nv(), 1);
  const double a0 = 1.2, rate0 = 6.0;
  Eigen::VectorXd q0(4), qd0(3);
  q0 << std::cos(a0 / 2), 0.0, std::sin(a0 / 2), 0.0;
  qd0 << 0.0, rate0, 0.0;
  const RunResult a = Simulate(ball.model, ball.loops, PassiveConfig(q0, qd0));
  const RunResult b = Simulate(
      revolute.model, revolute.loops,
      PassiveConfig(Eigen::VectorXd::Constant(1, a0), Eigen::VectorXd::Constant(1, rate0)));
  ASSERT_EQ(a.stats.status, RunStatus::kFinished) << a.stats.message;
  ASSERT_EQ(b.stats.status, RunStatus::kFinished) << b.stats.message;
  ASSERT_EQ(a.num_frames(), b.num_frames());
  double worst = 0.0, widest = 0.0;
  for (int k = 0; k < a.num_frames(); ++k) {
    const double angle = b.q[k], rate = b.qd[k];
    widest = std::max(widest, angle);
    const double* quat = &a.q[4 * k];
    const double* w = &a.qd[3 * k];
    // The same rotation (either sign of the quaternion) and the same angular velocity.
    const double sign = quat[0] * std::cos(angle / 2) + quat[2] * std::sin(angle / 2) < 0 ? -1 : 1;
    worst = std::max({worst, std::abs(sign * quat[0] - std::cos(angle / 2)), std::abs(quat[1]),
                      std::abs(sign * quat[2] - std::sin(angle / 2)), std::abs(quat[3])});
    worst = std::max({worst, std::abs(w[0]), std::abs(w[1] - rate) / rate0, std::abs(w[2])});
  }
  std::printf("swing through 90 deg (widest %.1f deg): ball against revolute %.3g\n",
              widest * 180 / 3.141592653589793, worst);
  EXPECT_GT(widest, 1.6);  // beyond 90 degrees
  EXPECT_LT(worst, 1e-8);
  EXPECT_LT(a.stats.energy_error_max, 1e-9);
}

// The Delta with its wrist (rod 1a to the platform) a ball joint in the spanning tree
// (tests/data/delta_ball.sdf, written by models/linkages/generate.py): the joint-space ODE
// runs it (q on its manifold, issue 43), its fall keeping its energy and its loops; the GGL
// DAE (method ida) keeps one position per velocity and is refused, naming the joint and what
// to use instead.
TEST(BallJointTest, AClosedLoopWithABallJointInItsTreeRunsWithBdfAndIdaIsRefused) {
  const SdfImport ball =
      ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/delta_ball.sdf");
  ASSERT_EQ(ball.model.ball_bodies.size(), 1u);
  ASSERT_FALSE(ball.loops.empty());
  RunConfig config;
  config.duration = 0.15;
  config.output_interval = 0.005;
  config.formulation = Formulation::kJoint;
  config.method = Method::kBdf;
  config.rtol = 1e-9;
  config.atol = 1e-11;
  config.drives.assign(static_cast<size_t>(ball.model.num_dofs()), DriveConfig{});
  ASSERT_NO_THROW(ValidateLoopRun(ball.model, ball.loops, config));
  const RunResult result = SimulateLoops(ball.model, ball.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  std::printf(
      "delta_ball (bdf, rtol 1e-9): energy %.3g, drift %.3g m %.3g rad %.3g, quaternion "
      "%.3g, steps %ld, cpu %.3g s\n",
      result.stats.energy_error_max, result.stats.drift_position_max,
      result.stats.drift_orientation_max, result.stats.drift_velocity_max,
      result.stats.quaternion_norm_error_max, result.stats.solver.steps, result.stats.cpu_s);
  EXPECT_EQ(result.stats.loops.mobility, 3);
  EXPECT_EQ(result.stats.trust, Trust::kOk) << result.stats.trust_reason;
  EXPECT_LT(result.stats.energy_error_max, 1e-6);
  EXPECT_LT(result.stats.drift_position_max, 1e-10);
  EXPECT_LT(result.stats.quaternion_norm_error_max, 1e-10);
  config.method = Method::kIda;
  try {
    ValidateLoopRun(ball.model, ball.loops, config);
    FAIL() << "accepted";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("ball joint 'wrist'"), std::string::npos) << message;
    EXPECT_NE(message.find("closed loops"), std::string::npos) << message;
    EXPECT_NE(message.find("use method bdf"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace mbstream
