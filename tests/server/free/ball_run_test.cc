// A run with a ball joint (JointType::kBall) through the engine: the frames' quaternion and
// angular velocity columns, the results files, the wire and the model description, every
// method keeping the quaternion unit, the energy kept, a sweep by coordinate name, and what
// the validation refuses (naming the joint and what to use instead).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "server/engine/engine.h"
#include "server/model/coordinate_names.h"
#include "server/model/model_builder.h"
#include "server/results/results_csv.h"
#include "server/runs/sweep_coordinates.h"
#include "server/sim/run_validation.h"
#include "server/wire/frame_conversion.h"
#include "server/wire/model_info.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

RigidInertia Bob(double mass, const Vector3d& com) {
  RigidInertia inertia;
  inertia.mass = mass;
  inertia.com = com;
  inertia.inertia_com << 0.02, 0.001, 0.0, 0.001, 0.03, 0.002, 0.0, 0.002, 0.04;
  return inertia;
}

// An arm on a revolute joint j1 (about z, 0.5 m up) carrying a bob on a ball joint 0.4 m out
// along its x axis, the joint frame turned 0.3 rad about x.
Model ArmAndBall() {
  ModelBuilder builder("arm_ball", "world");
  Joint joint;
  joint.name = "j1";
  joint.X_PJ.p = Vector3d(0, 0, 0.5);
  builder.AddMovingLink("a1", "world", joint, Bob(2.0, Vector3d(0.2, 0, 0)));
  Pose X_PJ;
  X_PJ.p = Vector3d(0.4, 0, 0);
  X_PJ.R = AxisAngleRotation(Vector3d::UnitX(), 0.3);
  builder.AddBallLink("bob", "a1", "ball", X_PJ, Bob(1.5, Vector3d(0.1, 0.05, -0.5)));
  return builder.Build();
}

// Passive, the bob turned and spinning.
RunConfig Config(const Model& model) {
  RunConfig config;
  config.duration = 1.0;
  config.output_interval = 0.01;
  config.formulation = Formulation::kJoint;
  config.rtol = 1e-10;
  config.atol = 1e-12;
  config.drives.resize(static_cast<size_t>(model.nv()));
  config.q0 = Eigen::VectorXd(5);
  const Eigen::Quaterniond quat(Eigen::AngleAxisd(1.0, Vector3d(1, 2, 0.5).normalized()));
  config.q0 << 0.2, quat.w(), quat.x(), quat.y(), quat.z();
  config.qd0 = Eigen::VectorXd(4);
  config.qd0 << 0.5, 1.0, -2.0, 3.0;
  return config;
}

std::string MessageOf(const Model& model, const RunConfig& config) {
  try {
    ValidateRun(model, config);
  } catch (const InputError& error) {
    return error.what();
  }
  return "accepted";
}

TEST(BallRunTest, FramesCarryTheQuaternionAndTheAngularVelocity) {
  const Model model = ArmAndBall();
  ASSERT_EQ(model.nq(), 5);
  ASSERT_EQ(model.nv(), 4);
  const RunConfig config = Config(model);
  ValidateRun(model, config);
  const RunResult result = Simulate(model, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  ASSERT_EQ(result.num_frames(), 101);
  EXPECT_EQ(result.num_dofs, 4);
  EXPECT_EQ(result.num_positions, 5);
  EXPECT_EQ(result.position_names,
            (std::vector<std::string>{"j1", "ball.qw", "ball.qx", "ball.qy", "ball.qz"}));
  EXPECT_EQ(result.joint_names, (std::vector<std::string>{"j1", "ball.wx", "ball.wy", "ball.wz"}));
  EXPECT_EQ(result.position_index, (std::vector<int>{0, -1, -1, -1}));
  for (int k = 0; k < 5; ++k) EXPECT_EQ(result.q[k], config.q0(k));

  const std::vector<results_csv::Series> series = results_csv::SeriesOf(result);
  EXPECT_EQ(series[0].file, "joints.csv");
  EXPECT_EQ(series[0].header, "t,j1,ball.qw,ball.qx,ball.qy,ball.qz");
  EXPECT_EQ(series[1].header, "t,j1,ball.wx,ball.wy,ball.wz");

  v1::Frame frame;
  FrameToProto(result, 100, &frame);
  EXPECT_EQ(frame.q_size(), 5);
  EXPECT_EQ(frame.qd_size(), 4);
  v1::RunInfo info;
  info.set_num_dofs(4);
  for (const std::string& name : result.joint_names) info.add_joint_names(name);
  info.set_num_positions(5);
  for (const std::string& name : result.position_names) info.add_position_names(name);
  info.set_has_torques(result.has_torques);
  const RunResult back = ResultFromFrames(info, {frame});
  EXPECT_EQ(back.positions(), 5);
  EXPECT_EQ(back.position_index, (std::vector<int>{0, -1, -1, -1}));
  EXPECT_EQ(back.q, std::vector<double>(&result.q[500], &result.q[505]));
}

TEST(BallRunTest, ModelInfoNamesEveryCoordinate) {
  const Model model = ArmAndBall();
  v1::ModelInfo info;
  DescribeModel(model, {}, &info);
  EXPECT_EQ(info.dofs(), 4);
  EXPECT_EQ(info.positions(), 5);
  ASSERT_EQ(info.position_names_size(), 5);
  EXPECT_EQ(info.position_names(1), "ball.qw");
  EXPECT_EQ(info.position_names(4), "ball.qz");
  ASSERT_EQ(info.velocity_names_size(), 4);
  EXPECT_EQ(info.velocity_names(3), "ball.wz");
  ASSERT_EQ(info.joints_size(), 2);
  EXPECT_EQ(info.joints(1).type(), "ball");
}

// Every method: the output frames' quaternions unit to 1e-12 (measured 2.2e-16 with each), and
// the energy of the passive mechanism kept (ERK at rtol 1e-12: 1e-12 of its scale).
TEST(BallRunTest, EveryMethodKeepsTheQuaternionUnitAndTheEnergy) {
  const Model model = ArmAndBall();
  for (const Method method :
       {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk, Method::kRk4, Method::kEuler}) {
    RunConfig config = Config(model);
    config.method = method;
    config.rtol = 1e-8;
    config.atol = 1e-10;
    config.fixed_step = 1e-4;
    ValidateRun(model, config);
    const RunResult result = Simulate(model, config);
    ASSERT_EQ(result.stats.status, RunStatus::kFinished)
        << MethodName(method) << ": " << result.stats.message;
    double worst = 0.0;
    for (int k = 0; k < result.num_frames(); ++k) {
      const double* quat = &result.q[5 * k + 1];
      worst = std::max(worst, std::abs(std::sqrt(quat[0] * quat[0] + quat[1] * quat[1] +
                                                 quat[2] * quat[2] + quat[3] * quat[3]) -
                                       1.0));
    }
    std::printf("%s: frames' | |quat| - 1 | at most %.2e, energy error %.2e\n", MethodName(method),
                worst, result.stats.energy_error_max);
    EXPECT_LT(worst, 1e-12) << MethodName(method);
  }
  RunConfig config = Config(model);
  config.method = Method::kErk;
  config.rtol = 1e-12;
  config.atol = 1e-14;
  const RunResult result = Simulate(model, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  const double e0 = result.kinetic[0] + result.potential[0];
  double drift = 0.0, scale = 0.0;
  for (int k = 0; k < result.num_frames(); ++k) {
    drift = std::max(drift, std::abs(result.kinetic[k] + result.potential[k] - e0));
    scale = std::max(scale, result.kinetic[k]);
  }
  std::printf("ERK at rtol 1e-12: energy drift %.3g J of %.3g J\n", drift, scale);
  EXPECT_GT(scale, 1.0);
  EXPECT_LT(drift, 1e-9 * scale);
}

// The arm prescribed along a sine (hybrid dynamics) swings the bob on its ball joint: the arm
// follows its reference exactly, the quaternion stays unit, the energy balance (the prescribed
// drive's work included) closes.
TEST(BallRunTest, APrescribedArmSwingsTheBallJointsBob) {
  const Model model = ArmAndBall();
  RunConfig config = Config(model);
  DriveConfig& arm = config.drives[0];
  arm.kind = DriveConfig::Kind::kPrescribed;
  arm.trajectory.offset = 0.2;
  arm.trajectory.amplitude = {0.5};
  arm.trajectory.omega = {3.0};
  arm.trajectory.phase = {0.0};
  config.qd0(0) = 1.5;
  ValidateRun(model, config);
  const RunResult result = Simulate(model, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  double arm_error = 0.0, norm = 0.0;
  for (int k = 0; k < result.num_frames(); ++k) {
    const double t = result.t[k];
    arm_error = std::max(arm_error, std::abs(result.q[5 * k] - (0.2 + 0.5 * std::sin(3.0 * t))));
    const double* quat = &result.q[5 * k + 1];
    norm = std::max(norm, std::abs(std::sqrt(quat[0] * quat[0] + quat[1] * quat[1] +
                                             quat[2] * quat[2] + quat[3] * quat[3]) -
                                   1.0));
  }
  std::printf("prescribed arm: reference error %.2e rad, | |quat| - 1 | %.2e, energy error %.2e\n",
              arm_error, norm, result.stats.energy_error_max);
  EXPECT_LT(arm_error, 1e-12);
  EXPECT_LT(norm, 1e-12);
  EXPECT_LT(result.stats.energy_error_max, 1e-6);
}

TEST(BallRunTest, ASweepNamesTheBallJointsCoordinates) {
  const Model model = ArmAndBall();
  v1::SweepDefinition definition;
  definition.add_grid()->set_path("initial_qd[ball.wy]");
  definition.add_grid()->set_path("initial_q[j1]");
  ResolveCoordinatePaths(model, &definition);
  EXPECT_EQ(definition.grid(0).path(), "initial_qd[2]");
  EXPECT_EQ(definition.grid(1).path(), "initial_q[0]");
  // The base's positions are the model's own: the ball joint's identity quaternion.
  ASSERT_EQ(definition.base().initial_q_size(), 5);
  EXPECT_EQ(definition.base().initial_q(1), 1.0);
  EXPECT_EQ(definition.base().initial_q(2), 0.0);
  EXPECT_EQ(definition.base().initial_qd_size(), 4);
}

TEST(BallRunTest, WhatTheBallJointDoesNotRunIsRefusedNamingIt) {
  const Model model = ArmAndBall();
  const std::string joint = "ball joint 'ball' (link 'bob')";
  RunConfig config = Config(model);
  config.formulation = Formulation::kBodyBaumgarte;
  std::string message = MessageOf(model, config);
  EXPECT_NE(message.find(joint), std::string::npos) << message;
  EXPECT_NE(message.find("use formulation joint"), std::string::npos) << message;

  config = Config(model);
  config.formulation = Formulation::kKinematic;
  message = MessageOf(model, config);
  EXPECT_NE(message.find(joint), std::string::npos) << message;
  EXPECT_NE(message.find("formulation kinematic"), std::string::npos) << message;

  config = Config(model);
  config.target.tcp_error_m = 1e-4;
  message = MessageOf(model, config);
  EXPECT_NE(message.find(joint), std::string::npos) << message;
  EXPECT_NE(message.find("accuracy target"), std::string::npos) << message;

  config = Config(model);
  config.drives[2].kind = DriveConfig::Kind::kPdServo;
  message = MessageOf(model, config);
  EXPECT_NE(message.find(joint + " has a drive on its coordinate 2"), std::string::npos) << message;

  config = Config(model);
  config.q0.tail(4) *= 1.1;
  message = MessageOf(model, config);
  EXPECT_NE(message.find(joint + ": initial_q's quaternion"), std::string::npos) << message;
  EXPECT_NE(message.find("has norm 1.1"), std::string::npos) << message;

  config = Config(model);
  config.q0 = Eigen::VectorXd::Zero(4);
  message = MessageOf(model, config);
  EXPECT_NE(message.find("a ball joint's 4 as qw qx qy qz"), std::string::npos) << message;

  // Within 1e-6 of unit: accepted, and normalised.
  config = Config(model);
  config.q0.tail(4) *= 1.0 + 5e-7;
  EXPECT_EQ(MessageOf(model, config), "accepted");
}

}  // namespace
}  // namespace mbstream
