// Consistent initial conditions of the body formulations, computed from the joint state:
// positions and orientations by forward kinematics of q0, velocities from (q0, qd0) by the
// velocity recursion, and accelerations and multipliers by the acceleration-level solve.
#pragma once

#include <Eigen/Core>

#include "server/body/body_mechanics.h"
#include "server/body/body_model.h"
#include "server/model/model.h"

namespace mbstream {

struct BodyInitialState {
  Eigen::VectorXd y;                 // size dae_size(): positions, velocities, multipliers
  Eigen::VectorXd yp;                // d/dt of y (multipliers' entries 0: algebraic)
  double constraint_residual = 0.0;  // max |g| and |G nu + g_t| at the start (a check)
};

// The positions and velocities (the first 13n entries; the multipliers 0) of the joint state
// (q0, qd0): forward kinematics and the velocity recursion.
Eigen::VectorXd BodyStateFromJoints(const Model& model, const BodyModel& bm,
                                    const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0);

// `mechanics` is used as a workspace (it must belong to `bm`). Returns false when the
// acceleration-level system is singular.
bool ConsistentInitialState(const Model& model, const BodyModel& bm, BodyMechanics& mechanics,
                            double t0, const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0,
                            BodyInitialState* state);

}  // namespace mbstream
