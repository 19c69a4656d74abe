// Moving a 6x6 spatial inertia across a joint, from the child body's frame to its parent's:
// I_P += X^T I_B X. The articulated-body and composite-rigid-body algorithms spend most of
// their time here, so joints about a coordinate axis with an unrotated origin (most robot
// arms, the IRB 1600 included) take a fast path: plane rotations and cross products
// instead of 3x3 matrix products.
#pragma once

#include "server/math/spatial.h"
#include "server/model/joint.h"

namespace mbstream {

namespace internal {

// M <- R M R^T for R the rotation by (cos c, sin s) about coordinate axis K.
template <int K>
inline void RotateAboutCoordinateAxis(double c, double s, Matrix3d& M) {
  constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
  for (int col = 0; col < 3; ++col) {
    const double mi = M(i, col), mj = M(j, col);
    M(i, col) = c * mi - s * mj;
    M(j, col) = s * mi + c * mj;
  }
  for (int row = 0; row < 3; ++row) {
    const double mi = M(row, i), mj = M(row, j);
    M(row, i) = c * mi - s * mj;
    M(row, j) = s * mi + c * mj;
  }
}

inline void RotateAboutCoordinateAxis(int k, double c, double s, Matrix3d& M) {
  switch (k) {
    case 0:
      return RotateAboutCoordinateAxis<0>(c, s, M);
    case 1:
      return RotateAboutCoordinateAxis<1>(c, s, M);
    default:
      return RotateAboutCoordinateAxis<2>(c, s, M);
  }
}

}  // namespace internal

// I_A += X_AB^T I_B X_AB, for X_AB = JointTransform(joint, q) (see joint_transform.h).
inline void AddInertiaAcrossJoint(const Joint& joint, const Pose& X_AB, const Matrix6d& I_B,
                                  Matrix6d* I_A) {
  const bool coordinate_rotation = joint.origin_rotation_identity &&
                                   (joint.type == JointType::kPrismatic || joint.axis_index >= 0);
  if (!coordinate_rotation) {
    AddInertiaToParent(X_AB, I_B, I_A);
    return;
  }
  Matrix3d A = I_B.topLeftCorner<3, 3>();
  Matrix3d B = I_B.topRightCorner<3, 3>();
  Matrix3d C = I_B.bottomRightCorner<3, 3>();
  if (joint.type == JointType::kRevolute) {
    const int k = joint.axis_index;
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const double c = X_AB.R(i, i), s = X_AB.R(j, i);
    internal::RotateAboutCoordinateAxis(k, c, s, A);
    internal::RotateAboutCoordinateAxis(k, c, s, B);
    internal::RotateAboutCoordinateAxis(k, c, s, C);
  }
  // Shift the reference point from Bo to Ao by p (see AddInertiaToParent), with cross
  // products instead of skew-matrix products: T = [p]x B^T, Q = [p]x C, W = [p]x Q^T.
  const Vector3d& p = X_AB.p;
  Matrix3d T, Q, W;
  for (int m = 0; m < 3; ++m) {
    T.col(m) = p.cross(Vector3d(B.row(m).transpose()));
    Q.col(m) = p.cross(Vector3d(C.col(m)));
  }
  for (int m = 0; m < 3; ++m) W.col(m) = p.cross(Vector3d(Q.row(m).transpose()));
  B += Q;
  I_A->topLeftCorner<3, 3>() += A + T + T.transpose() + W;
  I_A->topRightCorner<3, 3>() += B;
  I_A->bottomLeftCorner<3, 3>() += B.transpose();
  I_A->bottomRightCorner<3, 3>() += C;
}

}  // namespace mbstream
