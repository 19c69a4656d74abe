// A ball joint's kinematics (model.h): its 4 positions are the unit quaternion (qw qx qy qz) of
// R_JB, the child's rotation relative to the joint frame J fixed in the parent, and its 3
// velocities w_B the angular velocity of the child relative to the parent, in the child frame
// (MuJoCo's ball joint). The child's frame origin is the joint centre (J's origin), so in the
// algorithms' spatial vectors (server/math/spatial.h: motion [w; v_Bo], force [n_Bo; f]) the
// joint's motion subspace in the child frame is constant,
//   S = [I3; 0],  v_J = S qd = [w_B; 0],  dS/dt = 0 in the child frame,
// and the generalised force of a spatial force f_B = [n; f] is S^T f_B = n, the moment about
// the centre in the child frame. There is no singular orientation (no gimbal lock): S has full
// rank everywhere. All functions are inline and allocate nothing.
#pragma once

#include "server/kinematics/quaternion.h"
#include "server/math/spatial.h"
#include "server/model/joint.h"

namespace mbstream::ball_joint {

// X_PB = X_PJ * [R_JB(quat), 0] for the quaternion quat[0..3] (normalised first).
inline void Transform(const Joint& joint, const double* quat, Pose* X_PB) {
  X_PB->R.noalias() = joint.X_PJ.R * quaternion::Rotation(quat);
  X_PB->p = joint.X_PJ.p;
}

// v_J = S qd (qd: 3 values).
inline Vector6d Motion(const double* qd) {
  Vector6d v;
  v << qd[0], qd[1], qd[2], 0.0, 0.0, 0.0;
  return v;
}

}  // namespace mbstream::ball_joint
