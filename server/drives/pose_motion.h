// A prescribed pose (run_spec.proto, Drive.Pose): a free joint's position x y z and a free or
// ball joint's orientation R = Rz(yaw) Ry(pitch) Rx(roll) (fixed axes X, Y, Z: URDF's rpy),
// each a function of time with its first two derivatives, turned into the joint's
// coordinates (model.h): its positions (a free joint's x y z qw qx qy qz, a ball joint's
// qw qx qy qz), its velocities (vx vy vz in the world, wx wy wz in the body or child frame)
// and their rates, as RNEA takes them. Inline, allocate nothing.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "server/drives/trajectory.h"
#include "server/math/spatial.h"

namespace mbstream::pose_motion {

// R = Rz(yaw) Ry(pitch) Rx(roll) as the unit quaternion (qw qx qy qz) into quat[0..3]: the
// product of the three axis quaternions, so that it varies continuously with the angles (no
// sign flips between frames).
inline void Quaternion(double roll, double pitch, double yaw, double* quat) {
  const double cr = std::cos(0.5 * roll), sr = std::sin(0.5 * roll);
  const double cp = std::cos(0.5 * pitch), sp = std::sin(0.5 * pitch);
  const double cy = std::cos(0.5 * yaw), sy = std::sin(0.5 * yaw);
  quat[0] = cy * cp * cr + sy * sp * sr;
  quat[1] = cy * cp * sr - sy * sp * cr;
  quat[2] = cy * sp * cr + sy * cp * sr;
  quat[3] = sy * cp * cr - cy * sp * sr;
}

// roll, pitch, yaw of the rotation R (pitch in [-pi/2, pi/2]): R = Rz(yaw) Ry(pitch) Rx(roll).
inline Vector3d Angles(const Matrix3d& R) {
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  if (std::abs(R(2, 0)) < 1.0 - 1e-12) {
    return Vector3d(std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0)));
  }
  // Pitch +-pi/2: only roll -+ yaw is defined; put it all in yaw.
  return Vector3d(0.0, pitch, std::atan2(-R(0, 1), R(1, 1)));
}

// The angular velocity w and its rate w' of R(t) = Rz(yaw) Ry(pitch) Rx(roll), both in the
// fixed frame (the world for a free joint, the joint frame for a ball joint), from the
// angles' values, rates and second rates (rad, rad/s, rad/s^2). With a2 = Rz(yaw) e_y and
// a3 = Rz(yaw) Ry(pitch) e_x: w = yaw' e_z + pitch' a2 + roll' a3 and
// w' = yaw'' e_z + pitch'' a2 + pitch' (yaw' e_z x a2) + roll'' a3 + roll' ((yaw' e_z +
// pitch' a2) x a3).
inline void AngularMotion(const TrajectoryPoint& roll, const TrajectoryPoint& pitch,
                          const TrajectoryPoint& yaw, Vector3d* w, Vector3d* w_dot) {
  const double cy = std::cos(yaw.q), sy = std::sin(yaw.q);
  const double cp = std::cos(pitch.q), sp = std::sin(pitch.q);
  const Vector3d ez = Vector3d::UnitZ();
  const Vector3d a2(-sy, cy, 0.0);
  const Vector3d a3(cy * cp, sy * cp, -sp);
  const Vector3d w1 = yaw.qd * ez;
  const Vector3d w12 = w1 + pitch.qd * a2;
  *w = w12 + roll.qd * a3;
  *w_dot = yaw.qdd * ez + pitch.qdd * a2 + pitch.qd * w1.cross(a2) + roll.qdd * a3 +
           roll.qd * w12.cross(a3);
}

// A free joint's coordinates from its six components (x, y, z in m; roll, pitch, yaw in rad):
// q (7 values), qd (6) and qdd (6): the origin's position, velocity and acceleration in the
// world, then the angular velocity and its rate in the body frame (w_B = R^T w_W and, as
// R^T' w_W = -R^T (w_W x w_W) = 0, w_B' = R^T w_W').
inline void FreeCoordinates(const TrajectoryPoint* c, double* q, double* qd, double* qdd) {
  Vector3d w_W, w_dot_W;
  AngularMotion(c[3], c[4], c[5], &w_W, &w_dot_W);
  Quaternion(c[3].q, c[4].q, c[5].q, q + 3);
  const Eigen::Quaterniond rotation(q[3], q[4], q[5], q[6]);
  const Vector3d w_B = rotation.conjugate() * w_W;
  const Vector3d w_dot_B = rotation.conjugate() * w_dot_W;
  for (int k = 0; k < 3; ++k) {
    q[k] = c[k].q;
    qd[k] = c[k].qd;
    qdd[k] = c[k].qdd;
    qd[3 + k] = w_B(k);
    qdd[3 + k] = w_dot_B(k);
  }
}

// A ball joint's coordinates from its three components (roll, pitch, yaw about the joint
// frame's axes): q (4 values), qd (3) and qdd (3), the angular velocity relative to the joint
// frame and its rate, in the child frame.
inline void BallCoordinates(const TrajectoryPoint* c, double* q, double* qd, double* qdd) {
  Vector3d w_J, w_dot_J;
  AngularMotion(c[0], c[1], c[2], &w_J, &w_dot_J);
  Quaternion(c[0].q, c[1].q, c[2].q, q);
  const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
  const Vector3d w_C = rotation.conjugate() * w_J;
  const Vector3d w_dot_C = rotation.conjugate() * w_dot_J;
  for (int k = 0; k < 3; ++k) {
    qd[k] = w_C(k);
    qdd[k] = w_dot_C(k);
  }
}

}  // namespace mbstream::pose_motion
