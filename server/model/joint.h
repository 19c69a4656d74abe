// A joint that moves a body relative to its parent: its type, axis and properties.
#pragma once

#include <limits>
#include <string>

#include "server/math/spatial.h"

namespace mbstream {

// kFree: six degrees of freedom, the body's pose in the world (model.h: free bodies). Only a
// root body (parent kBase) has one; its axis, origin, limits, damping and armature are unused.
// kBall: three rotational degrees of freedom about the joint frame's origin (model.h: ball
// joints); its axis, limits, damping and armature are unused, its origin X_PJ is the joint frame.
enum class JointType { kRevolute, kPrismatic, kFree, kBall };

// "revolute", "prismatic", "free" or "ball".
const char* JointTypeName(JointType type);

struct JointLimits {
  // Position range: rad for revolute joints, m for prismatic; +-infinity when unlimited.
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  double velocity = std::numeric_limits<double>::infinity();  // rad/s or m/s
  double effort = std::numeric_limits<double>::infinity();    // N*m or N
};

struct Joint {
  std::string name;
  JointType type = JointType::kRevolute;
  Pose X_PJ;                          // joint frame J in the parent body frame P (URDF origin)
  Vector3d axis = Vector3d::UnitZ();  // unit vector in J (and in the child body frame)
  JointLimits limits;
  double damping = 0.0;   // viscous: N*m*s/rad or N*s/m; force -damping * qd
  double armature = 0.0;  // rotor (reflected) inertia: kg*m^2 or kg, added to M(q)(i, i)

  // Derived by ModelBuilder, for fast paths in the algorithms:
  int axis_index = -1;                    // 0, 1, 2 when axis is exactly +x, +y, +z; else -1
  bool origin_rotation_identity = false;  // X_PJ.R is exactly the identity
  // 0, 1, 2 when X_PJ.p lies on that coordinate axis (one nonzero component), kNoOffset when
  // X_PJ.p = 0, kAnyOffset otherwise.
  int offset_axis = -1;
  // 5 K + (offset_axis, or 4 for kAnyOffset) for a revolute joint about coordinate axis K with
  // an unrotated origin (0..14), else -1: the dynamics kernels' dispatch index.
  int axis_kernel = -1;
};

inline constexpr int kAnyOffset = -1;
inline constexpr int kNoOffset = 3;

// Sets the derived fields of `joint` from its axis and origin.
void DeriveJointShape(Joint& joint);

}  // namespace mbstream
