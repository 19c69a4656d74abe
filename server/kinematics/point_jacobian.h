// Geometric Jacobian of a frame's origin.
#pragma once

#include <Eigen/Core>

#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

// Writes into J (6 x nv, model.h) the geometric Jacobian of frame `frame`'s origin, both in
// the world frame: rows 0..2 angular velocity (rad/s), rows 3..5 the origin's linear
// velocity (m/s), per unit joint velocity. ForwardKinematics must have run for the same q.
// Allocates nothing.
void PointJacobian(const Model& model, const Data& data, int frame, Eigen::Ref<Eigen::MatrixXd> J);

}  // namespace mbstream
