// Joint-space mass matrix by the composite-rigid-body algorithm (Featherstone, RBDA, 6.2).
#pragma once

#include <Eigen/Core>

#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

// M(q) (num_dofs x num_dofs, symmetric, both halves filled; rotor inertia on the diagonal)
// into data.M (returned). Writes data.X_parent and data.IA. Allocates nothing.
const Eigen::MatrixXd& Crba(const Model& model, Data& data,
                            const Eigen::Ref<const Eigen::VectorXd>& q);

}  // namespace mbstream
