// Mechanical energy of the mechanism.
#pragma once

#include <Eigen/Core>

#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

// Kinetic energy (J) at (q, qd): bodies plus rotor inertia (armature * qd^2 / 2).
// Writes data.X_parent and data.v. Allocates nothing.
double KineticEnergy(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q,
                     const Eigen::Ref<const Eigen::VectorXd>& qd);

// KineticEnergy at (q, qd) when ForwardKinematics (or BodyKinematics) has just run for the
// same q: reuses its data.X_parent instead of recomputing the joint transforms; the same
// value, bit for bit. Writes data.v. Allocates nothing.
double KineticEnergyAfterKinematics(const Model& model, Data& data,
                                    const Eigen::Ref<const Eigen::VectorXd>& qd);

// Potential energy (J) of gravity at q, zero with every centre of mass at the base origin's
// height (-m g . c). ForwardKinematics (or BodyKinematics) must have run for the same q.
double PotentialEnergy(const Model& model, const Data& data);

}  // namespace mbstream
