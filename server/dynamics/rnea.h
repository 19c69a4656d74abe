// Inverse dynamics by the recursive Newton-Euler algorithm (Featherstone, RBDA, 5.3).
#pragma once

#include <Eigen/Core>

#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

using ConstVectorRef = const Eigen::Ref<const Eigen::VectorXd>&;

// tau = M(q) qdd + C(q, qd) qd + g(q): the joint forces (N*m or N, size num_dofs) that give
// accelerations qdd at (q, qd) under model.gravity, rotor inertia included, joint damping
// excluded (it is an applied force: add damping * qd to get the drive effort). Writes
// data.tau (returned), data.X_parent, data.v, data.a, data.f. Allocates nothing.
const Eigen::VectorXd& Rnea(const Model& model, Data& data, ConstVectorRef q, ConstVectorRef qd,
                            ConstVectorRef qdd);

// h(q, qd) = C(q, qd) qd + g(q) into data.tau (returned): Rnea with qdd = 0.
const Eigen::VectorXd& NonlinearEffects(const Model& model, Data& data, ConstVectorRef q,
                                        ConstVectorRef qd);

// g(q), the generalized gravity force, into data.gravity_torque (returned).
const Eigen::VectorXd& GravityVector(const Model& model, Data& data, ConstVectorRef q);

}  // namespace mbstream
