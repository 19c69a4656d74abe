// Shared helpers of the body-formulation tests: the IRB 1600, its scenes, random states.
#pragma once

#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "server/body/body_model.h"
#include "server/body/quaternion.h"
#include "server/drives/drive_set.h"
#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream::testing {

// Cut joints of every kind the body formulations close loops with, at arbitrary frames (the
// derivatives hold whether or not the loops are closed), one with the base as its child side;
// for the branching model (testing::BranchingModel, 5 moving bodies).
inline std::vector<LoopClosure> CutsOfEveryKind() {
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -1).normalized()).toRotationMatrix();
  std::vector<LoopClosure> loops(3);
  loops[0].type = LoopJointType::kRevolute;
  loops[0].body_a = 0;
  loops[0].X_AJ = Pose{turn, Vector3d(0.1, -0.2, 0.3)};
  loops[0].body_b = 3;
  loops[0].X_BJ = Pose{turn.transpose(), Vector3d(-0.05, 0.1, 0.2)};
  loops[0].axis = Vector3d(0.3, -0.4, 0.5).normalized();
  loops[1].type = LoopJointType::kPrismatic;
  loops[1].body_a = 2;
  loops[1].X_AJ = Pose{turn * turn, Vector3d(0.2, 0.1, -0.1)};
  loops[1].body_b = kBase;
  loops[1].X_BJ = Pose{turn.transpose(), Vector3d(0.3, 0.0, 0.4)};
  loops[1].axis = Vector3d(-0.1, 0.9, 0.2).normalized();
  loops[2].type = LoopJointType::kBall;
  loops[2].body_a = 1;
  loops[2].X_AJ = Pose{Eigen::Matrix3d::Identity(), Vector3d(0.0, 0.3, 0.1)};
  loops[2].body_b = 2;
  loops[2].X_BJ = Pose{turn, Vector3d(0.1, 0.0, -0.2)};
  return loops;
}

// A random (inconsistent) body state: positions, unit-ish quaternions, velocities.
inline Eigen::VectorXd RandomBodyState(const BodyModel& bm, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd y(bm.dae_size());
  for (int i = 0; i < y.size(); ++i) y(i) = u(rng);
  for (int b = 0; b < bm.n; ++b) {
    Vector4d e = y.segment<4>(BodyModel::quaternion(b));
    y.segment<4>(BodyModel::quaternion(b)) = e / e.norm() * (1.0 + 0.01 * u(rng));
  }
  for (int k = 0; k < bm.m; ++k) y(bm.multiplier(k)) *= 100.0;
  return y;
}

// The seed run with its joints prescribed by position (not velocity sources) as a
// variant, and the seed servo, for drives of every kind.
inline RunConfig SeedRun(Formulation formulation, Method method, double rtol) {
  RunConfig config = Scene("seed-run");
  config.formulation = formulation;
  config.method = method;
  config.rtol = rtol;
  config.atol = rtol * 1e-2;
  return config;
}

// Drives for the branching test model (tests/common): every joint prescribed by a sine
// (position-level), or a mix of servo, torque and passive drives.
inline RunConfig BranchingDrives(const Model& model, bool all_prescribed) {
  RunConfig config;
  config.drives.resize(model.num_dofs());
  for (int i = 0; i < model.num_dofs(); ++i) {
    DriveConfig& drive = config.drives[i];
    drive.trajectory.kind = Trajectory::Kind::kSine;
    drive.trajectory.offset = 0.05 * i;
    drive.trajectory.amplitude = {0.3 + 0.1 * i};
    drive.trajectory.omega = {1.0 + 0.5 * i};
    drive.trajectory.phase = {0.2 * i};
    if (all_prescribed) {
      drive.kind = DriveConfig::Kind::kPrescribed;
    } else if (i % 3 == 0) {
      drive.kind = DriveConfig::Kind::kPdServo;
      drive.kp = 200.0;
      drive.kd = 10.0;
    } else if (i % 3 == 1) {
      drive.kind = DriveConfig::Kind::kTorque;
      drive.constant = 0.5;
      drive.amplitude = 2.0;
      drive.omega = 3.0;
    }
  }
  config.q0 = Eigen::VectorXd::Zero(model.num_dofs());
  config.qd0 = Eigen::VectorXd::Constant(model.num_dofs(), 0.2);
  config.duration = 2.0;
  config.output_interval = 0.01;
  config.want_torques = true;
  return config;
}

}  // namespace mbstream::testing
