// Forward dynamics by the articulated-body algorithm (Featherstone, RBDA, 7.3).
#pragma once

#include <Eigen/Core>

#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

// qdd = M(q)^-1 (tau - h(q, qd)): joint accelerations (size num_dofs) for joint forces tau
// (N*m or N; damping not included: pass tau - damping * qd) under model.gravity, rotor
// inertia included. Writes data.qdd (returned) and the ABA workspace. Allocates nothing.
const Eigen::VectorXd& Aba(const Model& model, Data& data,
                           const Eigen::Ref<const Eigen::VectorXd>& q,
                           const Eigen::Ref<const Eigen::VectorXd>& qd,
                           const Eigen::Ref<const Eigen::VectorXd>& tau);

}  // namespace mbstream
