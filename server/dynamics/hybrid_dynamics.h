// Hybrid dynamics (Featherstone, RBDA 9.2): forward dynamics of some joints and inverse
// dynamics of the others in one O(n) articulated-body pass.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

// Joints with prescribed[i] != 0 have their acceleration given (qdd(i); their tau(i) is
// ignored) and get the joint force that produces it (N*m or N, rotor inertia included,
// damping not) in data.tau(i); the others have their force given (tau(i)) and get their
// acceleration. Writes data.qdd (all joints, returned), data.tau's prescribed entries and the
// ABA workspace. With no joint prescribed it is Aba (aba.h), with every joint prescribed
// RNEA (rnea.h), to round-off. `qdd` may alias data.qdd. Allocates nothing.
const Eigen::VectorXd& HybridAba(const Model& model, Data& data,
                                 const Eigen::Ref<const Eigen::VectorXd>& q,
                                 const Eigen::Ref<const Eigen::VectorXd>& qd,
                                 const Eigen::Ref<const Eigen::VectorXd>& tau,
                                 const Eigen::Ref<const Eigen::VectorXd>& qdd,
                                 const std::vector<unsigned char>& prescribed);

}  // namespace mbstream
