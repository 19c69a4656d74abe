// A point of a body, in the world, as contact sees it: its velocity and the generalised
// force of a force applied there (J^T f). The same columns as PointJacobian
// (server/kinematics/point_jacobian.h, free joints included), walked up the body's chain
// without forming J: O(depth), no allocation. BodyKinematics (or ForwardKinematics) must
// have run for the same q.
#pragma once

#include <Eigen/Core>

#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

// The velocity (m/s, world) of the material point of `body` at world point p; 0 for kBase.
Vector3d PointVelocity(const Model& model, const Data& data, int body, const Vector3d& p,
                       const Eigen::VectorXd& qd);

// tau += J(p)^T [0; f]: the generalised force of force f (N, world) on `body` at world point
// p; nothing for kBase.
void AddPointForce(const Model& model, const Data& data, int body, const Vector3d& p,
                   const Vector3d& f, Eigen::VectorXd* tau);

}  // namespace mbstream
