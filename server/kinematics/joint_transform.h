// The pose of a body in its parent for a joint value: URDF convention, joint origin first,
// then the joint's motion about (or along) its axis.
#pragma once

#include "server/math/spatial.h"
#include "server/model/joint.h"

namespace mbstream {

// X_PB = X_PJ * X_JB(q), q in rad (revolute) or m (prismatic).
inline Pose JointTransform(const Joint& joint, double q) {
  if (joint.type == JointType::kRevolute) {
    return Pose{joint.X_PJ.R * AxisAngleRotation(joint.axis, q), joint.X_PJ.p};
  }
  return Pose{joint.X_PJ.R, joint.X_PJ.p + joint.X_PJ.R * (joint.axis * q)};
}

}  // namespace mbstream
