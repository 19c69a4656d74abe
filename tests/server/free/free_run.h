// Test helpers for free bodies: a model's ODE with its drives integrated from a state, and a
// model's total spatial momentum in the world frame.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <string>
#include <vector>

#include "server/drives/drive_set.h"
#include "server/dynamics/energy.h"
#include "server/integrate/integrator.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/sim/joint_space_ode.h"

namespace mbstream::testing {

// A model, its drives and its ODE, integrated by `method` from y0.
struct FreeRun {
  FreeRun(Model model_in, const std::vector<DriveConfig>& drive_configs)
      : model(std::move(model_in)), drives(model, drive_configs), ode(model, drives) {}
  explicit FreeRun(Model model_in) : FreeRun(model_in, std::vector<DriveConfig>(model_in.nv())) {}

  void Start(const Eigen::VectorXd& y0, Method method, double rtol, double step = 1e-3) {
    y = y0;
    IntegratorOptions options;
    options.method = method;
    options.rtol = rtol;
    options.atol = rtol * 1e-2;
    options.fixed_step = step;
    integrator = MakeIntegrator(ode, 0.0, y.data(), options);
  }
  void AdvanceTo(double t) {
    const AdvanceResult result = integrator->AdvanceTo(t, y.data());
    ASSERT_EQ(result.status, IntegratorStatus::kOk) << result.message;
    ASSERT_TRUE(ode.EvaluateOutputs(t, y.data(), false));
  }

  Model model;
  DriveSet drives;
  JointSpaceOde ode;
  Eigen::VectorXd y;
  std::unique_ptr<Integrator> integrator;
};

// A servo along offset + amplitude sin(omega t) (rad or m), gains kp and kd.
inline DriveConfig SineServo(double kp, double kd, double offset, double amplitude, double omega) {
  DriveConfig drive;
  drive.kind = DriveConfig::Kind::kPdServo;
  drive.kp = kp;
  drive.kd = kd;
  drive.trajectory.offset = offset;
  drive.trajectory.amplitude = {amplitude};
  drive.trajectory.omega = {omega};
  drive.trajectory.phase = {0.0};
  return drive;
}

// The bodies' total spatial momentum (angular about the world origin, then linear), in the
// world frame, leaving out the bodies named in `without`.
inline Vector6d SpatialMomentum(const Model& model, Data& data, const Eigen::VectorXd& q,
                                const Eigen::VectorXd& qd,
                                const std::set<std::string>& without = {}) {
  ForwardKinematics(model, data, q);
  KineticEnergyAfterKinematics(model, data, qd);
  Vector6d h = Vector6d::Zero();
  for (int i = 0; i < model.num_bodies(); ++i) {
    if (without.count(model.bodies[i].name)) continue;
    h += ForceToParent(data.X_world[i], model.bodies[i].inertia.Apply(data.v[i]));
  }
  return h;
}

}  // namespace mbstream::testing
