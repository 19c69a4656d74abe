// A free joint's kinematics (model.h): its 7 positions q = [p_WB; quat_WB] (x y z qw qx qy qz)
// and 6 velocities qd = [v_WB in the world; w_B in the body] against the algorithms' spatial
// vectors in the body frame (server/math/spatial.h: motion [w; v_Bo], force [n_Bo; f]).
//
// With R = R_WB, the joint's motion subspace, columns in qd's order, rows [angular; linear] in
// the body frame, is
//   S(q) = [[0, 1], [R^T, 0]],  so  v_B = S qd = [w_B; R^T v_WB],
// its rate times qd is c = dS/dt qd = [0; -w_B x (R^T v_WB)], and the generalised force of a
// spatial force f_B = [n; f] is S^T f_B = [R f; n] (the force in the world, the moment about
// the body origin in the body). S is square and invertible, which the algorithms use for the
// root: a free body's whole articulated inertia meets the world. All functions are inline and
// allocate nothing.
#pragma once

#include "server/kinematics/quaternion.h"
#include "server/math/spatial.h"

namespace mbstream::free_joint {

// R_WB of the quaternion (qw, qx, qy, qz) = quat[0..3], normalised first.
inline Matrix3d Rotation(const double* quat) { return quaternion::Rotation(quat); }

// X_WB for positions q (7 values).
inline void Transform(const double* q, Pose* X_WB) {
  X_WB->R = Rotation(q + 3);
  X_WB->p = Vector3d(q[0], q[1], q[2]);
}

// v_B = S qd (qd: 6 values).
inline Vector6d Motion(const Matrix3d& R, const double* qd) {
  Vector6d v;
  v.head<3>() = Vector3d(qd[3], qd[4], qd[5]);
  v.tail<3>().noalias() = R.transpose() * Vector3d(qd[0], qd[1], qd[2]);
  return v;
}

// c = dS/dt qd for the body's spatial velocity v_B = S qd.
inline Vector6d RateProduct(const Vector6d& v_B) {
  Vector6d c;
  c.head<3>().setZero();
  c.tail<3>() = -v_B.head<3>().cross(v_B.tail<3>());
  return c;
}

// tau = S^T f_B (6 values).
inline void ForceToCoordinates(const Matrix3d& R, const Vector6d& f_B, double* tau) {
  const Vector3d f_W = R * f_B.tail<3>();
  for (int k = 0; k < 3; ++k) {
    tau[k] = f_W(k);
    tau[3 + k] = f_B(k);
  }
}

// f_B = S^-T tau: the spatial force whose generalised force is tau.
inline Vector6d CoordinatesToForce(const Matrix3d& R, const double* tau) {
  Vector6d f;
  f.head<3>() = Vector3d(tau[3], tau[4], tau[5]);
  f.tail<3>().noalias() = R.transpose() * Vector3d(tau[0], tau[1], tau[2]);
  return f;
}

// qdd = S^-1 a for a spatial acceleration a = S qdd (6 values written).
inline void MotionToCoordinates(const Matrix3d& R, const Vector6d& a, double* qdd) {
  const Vector3d a_W = R * a.tail<3>();
  for (int k = 0; k < 3; ++k) {
    qdd[k] = a_W(k);
    qdd[3 + k] = a(k);
  }
}

// q' = G(q) qd (7 values): p' = v_WB, quat' = 1/2 quat (x) (0, w_B).
inline void PositionRate(const double* q, const double* qd, double* q_rate) {
  q_rate[0] = qd[0];
  q_rate[1] = qd[1];
  q_rate[2] = qd[2];
  quaternion::Rate(q + 3, qd + 3, q_rate + 3);
}

// Scales the quaternion q[3..6] to unit length; returns its norm before.
inline double NormaliseQuaternion(double* q) { return quaternion::Normalise(q + 3); }

}  // namespace mbstream::free_joint
