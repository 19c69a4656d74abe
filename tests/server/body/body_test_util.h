// Shared helpers of the body-formulation tests: the IRB 1600, its scenes, random states.
#pragma once

#include <random>

#include <Eigen/Core>

#include "server/body/body_model.h"
#include "server/body/quaternion.h"
#include "server/drives/drive_set.h"
#include "server/model/model.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream::testing {

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
