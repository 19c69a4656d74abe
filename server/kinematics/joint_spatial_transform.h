// Spatial vectors across a joint, specialised by the joint's shape.
//
// Most robot arms (the IRB 1600 included) have joints whose origin is unrotated and whose
// axis is a coordinate axis: X_PB = (R, p) with R a plane rotation by (cos, sin) about
// axis K and p constant. Moving a motion or force vector across such a joint then takes a
// plane rotation and one cross product instead of two 3x3 products. The recursive
// algorithms (ABA, RNEA) dispatch once per body on the joint's shape (DispatchJointShape)
// and call the transforms below with the shape as a template argument, so the fast paths
// are inlined and no branch is taken per operation.
#pragma once

#include <type_traits>

#include "server/math/spatial.h"
#include "server/model/joint.h"

namespace mbstream {

// A joint's shape, as a compile-time argument: 0, 1, 2 = rotation about that coordinate
// axis (revolute joint, unrotated origin); kTranslatingJoint = R = I (prismatic joint,
// unrotated origin); kGeneralJoint = anything else (full pose).
inline constexpr int kTranslatingJoint = -1;
inline constexpr int kGeneralJoint = -2;

inline int JointShape(const Joint& joint) {
  if (!joint.origin_rotation_identity) return kGeneralJoint;
  if (joint.type == JointType::kPrismatic) return kTranslatingJoint;
  return joint.axis_index >= 0 ? joint.axis_index : kGeneralJoint;
}

// Calls f(std::integral_constant<int, JointShape(joint)>{}).
template <typename F>
inline decltype(auto) DispatchJointShape(const Joint& joint, F&& f) {
  switch (JointShape(joint)) {
    case 0:
      return f(std::integral_constant<int, 0>{});
    case 1:
      return f(std::integral_constant<int, 1>{});
    case 2:
      return f(std::integral_constant<int, 2>{});
    case kTranslatingJoint:
      return f(std::integral_constant<int, kTranslatingJoint>{});
    default:
      return f(std::integral_constant<int, kGeneralJoint>{});
  }
}

namespace internal {

// x <- R x (kTranspose: R^T x) for R the rotation about coordinate axis K whose (cos, sin)
// are read from the rotation matrix itself (see CoordinateRotation in joint_transform.h).
template <int K, bool kTranspose>
inline Vector3d RotateAboutAxis(const Matrix3d& R, const Vector3d& x) {
  constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
  const double c = R(i, i), s = kTranspose ? -R(j, i) : R(j, i);
  Vector3d r;
  r(K) = x(K);
  r(i) = c * x(i) - s * x(j);
  r(j) = s * x(i) + c * x(j);
  return r;
}

}  // namespace internal

// MotionToChild (server/math/spatial.h) for X_AB = JointTransform(joint, q), Shape =
// JointShape(joint): m_B = [R^T w; R^T (v + w x p)].
template <int Shape>
inline Vector6d MotionToChildAcross(const Pose& X_AB, const Vector6d& m_A) {
  if constexpr (Shape == kGeneralJoint) {
    return MotionToChild(X_AB, m_A);
  } else {
    const Vector3d w = m_A.head<3>();
    const Vector3d v = m_A.tail<3>() + w.cross(X_AB.p);
    Vector6d m_B;
    if constexpr (Shape == kTranslatingJoint) {
      m_B << w, v;
    } else {
      m_B << internal::RotateAboutAxis<Shape, true>(X_AB.R, w),
          internal::RotateAboutAxis<Shape, true>(X_AB.R, v);
    }
    return m_B;
  }
}

// ForceToParent (server/math/spatial.h) for X_AB = JointTransform(joint, q), Shape =
// JointShape(joint): f_A = [R n + p x (R f); R f].
template <int Shape>
inline Vector6d ForceToParentAcross(const Pose& X_AB, const Vector6d& f_B) {
  if constexpr (Shape == kGeneralJoint) {
    return ForceToParent(X_AB, f_B);
  } else {
    Vector3d n = f_B.head<3>(), f = f_B.tail<3>();
    if constexpr (Shape != kTranslatingJoint) {
      n = internal::RotateAboutAxis<Shape, false>(X_AB.R, n);
      f = internal::RotateAboutAxis<Shape, false>(X_AB.R, f);
    }
    Vector6d f_A;
    f_A << n + X_AB.p.cross(f), f;
    return f_A;
  }
}

}  // namespace mbstream
