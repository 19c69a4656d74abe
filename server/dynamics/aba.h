// Forward dynamics by the articulated-body algorithm (Featherstone, RBDA, 7.3).
#pragma once

#include <vector>

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

// Hybrid dynamics (Featherstone, RBDA 9.2), O(n): joints with prescribed[i] != 0 have their
// acceleration given (qdd(i); their tau(i) is ignored) and get the joint force that
// produces it (N*m or N, rotor inertia included, damping not) in data.tau(i); the others
// have their force given (tau(i)) and get their acceleration. Writes data.qdd (all joints,
// returned), data.tau's prescribed entries and the ABA workspace. With no joint prescribed
// it equals Aba. `qdd` may alias data.qdd. Allocates nothing.
const Eigen::VectorXd& HybridAba(const Model& model, Data& data,
                                 const Eigen::Ref<const Eigen::VectorXd>& q,
                                 const Eigen::Ref<const Eigen::VectorXd>& qd,
                                 const Eigen::Ref<const Eigen::VectorXd>& tau,
                                 const Eigen::Ref<const Eigen::VectorXd>& qdd,
                                 const std::vector<unsigned char>& prescribed);

}  // namespace mbstream
