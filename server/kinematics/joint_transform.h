// The pose of a body in its parent for a joint value: URDF convention, joint origin first,
// then the joint's motion about (or along) its axis.
#pragma once

#include <cmath>

#include "server/kinematics/joint_spatial_transform.h"
#include "server/math/spatial.h"
#include "server/model/joint.h"

namespace mbstream {

// Rotation by angle (cos c, sin s) about coordinate axis k (0 = x, 1 = y, 2 = z).
inline Matrix3d CoordinateRotation(int k, double c, double s) {
  Matrix3d r = Matrix3d::Identity();
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  r(i, i) = c;
  r(i, j) = -s;
  r(j, i) = s;
  r(j, j) = c;
  return r;
}

// Writes X_PB = X_PJ * X_JB(q), q in rad (revolute) or m (prismatic), into *X_PB.
inline void JointTransform(const Joint& joint, double q, Pose* X_PB) {
  if (joint.type == JointType::kRevolute) {
    double s, c;
    ::sincos(q, &s, &c);
    if (joint.axis_index >= 0 && joint.origin_rotation_identity) {
      X_PB->R = CoordinateRotation(joint.axis_index, c, s);
    } else {
      const Matrix3d R_JB = joint.axis_index >= 0 ? CoordinateRotation(joint.axis_index, c, s)
                                                  : AxisAngleRotation(joint.axis, q);
      X_PB->R.noalias() = joint.X_PJ.R * R_JB;
    }
    X_PB->p = joint.X_PJ.p;
  } else {
    X_PB->R = joint.X_PJ.R;
    X_PB->p = joint.X_PJ.p + joint.X_PJ.R * (joint.axis * q);
  }
}

// JointTransform for Shape = JointShape(joint) known at compile time: a revolute joint about a
// coordinate axis with an unrotated origin is one sincos and a plane rotation.
template <int Shape>
inline void JointTransformOfShape(const Joint& joint, double q, Pose* X_PB) {
  if constexpr (Shape >= 0) {
    double s, c;
    ::sincos(q, &s, &c);
    constexpr int i = (Shape + 1) % 3, j = (Shape + 2) % 3;
    Matrix3d& R = X_PB->R;
    R.setZero();
    R(Shape, Shape) = 1.0;
    R(i, i) = c;
    R(i, j) = -s;
    R(j, i) = s;
    R(j, j) = c;
    X_PB->p = joint.X_PJ.p;
  } else {
    JointTransform(joint, q, X_PB);
  }
}

}  // namespace mbstream
