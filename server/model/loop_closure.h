// A joint cut out of the spanning tree to make it a tree: it closes a kinematic loop and
// becomes a constraint on the tree's joint coordinates (server/kinematics/loop_constraints.h).
//
// The tree is a Model (model.h); its cut joints travel beside it (a list of LoopClosure), so
// that a tree stays exactly what it was.
//
// Both sides carry a copy of the cut joint's frame J: frame A fixed in body `body_a` (the
// joint's parent side) and frame B fixed in body `body_b` (its child side). When the loop is
// closed, A and B coincide up to the motion the joint allows: a rotation about the axis
// (revolute), a translation along it (prismatic), any rotation (ball), none (fixed).
#pragma once

#include <string>

#include "server/math/spatial.h"

namespace mbstream {

enum class LoopJointType { kRevolute, kPrismatic, kBall, kFixed };

// "revolute", "prismatic", "ball", "fixed".
const char* LoopJointTypeName(LoopJointType type);

// Constraint equations of a cut joint of this type: 6 less the joint's freedoms.
int LoopJointEquations(LoopJointType type);

struct LoopClosure {
  std::string name;   // the cut joint's name in the model file
  std::string where;  // "FILE:LINE" of the joint in the model file, for messages
  LoopJointType type = LoopJointType::kRevolute;
  int body_a = -1;                    // parent side: body index or kBase
  Pose X_AJ;                          // the joint frame in body_a's frame
  int body_b = -1;                    // child side: body index or kBase
  Pose X_BJ;                          // the joint frame in body_b's frame
  Vector3d axis = Vector3d::UnitZ();  // unit, in J (revolute, prismatic)
};

}  // namespace mbstream
