// A free body's initial state given by name (RunSpec.initial_bodies), over the run's
// initial_q and initial_qd: each part given replaces the free joint's coordinates (x y z,
// qw qx qy qz; vx vy vz, wx wy wz: docs/free_bodies.md), each part absent keeps them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "server/model/model.h"

namespace mbstream {

struct InitialBodyState {
  std::string name;                                   // the free joint's name
  std::optional<Eigen::Vector3d> position{};          // m, p_WB: the body origin in the world
  std::optional<Eigen::Vector4d> quaternion{};        // qw qx qy qz of R_WB, unit within 1e-6
  std::optional<Eigen::Vector3d> linear_velocity{};   // m/s, v_WB, in the world frame
  std::optional<Eigen::Vector3d> angular_velocity{};  // rad/s, w_B, in the body frame
  bool operator==(const InitialBodyState&) const = default;
};

// The index in model.bodies of the free body whose joint is named `name`, or -1.
int FindFreeBody(const Model& model, const std::string& name);

// Writes each entry's parts over the free joint's coordinates of q (nq values) and qd (nv
// values); the quaternion as given (the caller normalises). Every name must be a free
// body's (ValidateRun).
void ApplyInitialBodies(const Model& model, const std::vector<InitialBodyState>& bodies, double* q,
                        double* qd);

}  // namespace mbstream
