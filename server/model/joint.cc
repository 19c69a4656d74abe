#include "server/model/joint.h"

namespace mbstream {

const char* JointTypeName(JointType type) {
  switch (type) {
    case JointType::kRevolute:
      return "revolute";
    case JointType::kPrismatic:
      return "prismatic";
    case JointType::kFree:
      return "free";
    case JointType::kBall:
      return "ball";
  }
  return "unknown";
}

void DeriveJointShape(Joint& joint) {
  if (joint.type == JointType::kFree || joint.type == JointType::kBall) {
    // no axis: never one of the kernels' shapes
    joint.axis_index = -1;
    joint.origin_rotation_identity = false;
    joint.offset_axis = kAnyOffset;
    joint.axis_kernel = -1;
    return;
  }
  joint.axis_index = -1;
  for (int k = 0; k < 3; ++k) {
    if (joint.axis == Vector3d::Unit(k)) joint.axis_index = k;
  }
  joint.origin_rotation_identity = joint.X_PJ.R == Matrix3d::Identity();
  const Vector3d& p = joint.X_PJ.p;
  const int nonzero = (p.x() != 0.0) + (p.y() != 0.0) + (p.z() != 0.0);
  joint.offset_axis = kAnyOffset;
  if (nonzero == 0) joint.offset_axis = kNoOffset;
  for (int k = 0; k < 3 && nonzero == 1; ++k) {
    if (p(k) != 0.0) joint.offset_axis = k;
  }
  joint.axis_kernel = -1;
  if (joint.type == JointType::kRevolute && joint.origin_rotation_identity &&
      joint.axis_index >= 0) {
    joint.axis_kernel =
        5 * joint.axis_index + (joint.offset_axis == kAnyOffset ? 4 : joint.offset_axis);
  }
}

}  // namespace mbstream
