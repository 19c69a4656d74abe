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
//
// A coupling of two tree joints (a URDF <mimic>, kMimic) travels the same way: the joint of
// body_b follows the joint of body_a, q(body_b) = multiplier * q(body_a) + offset, one
// equation on the coordinates (rad or m; both bodies move, the frames and axis are unused).
#pragma once

#include <string>

#include "server/math/spatial.h"

namespace mbstream {

enum class LoopJointType { kRevolute, kPrismatic, kBall, kFixed, kMimic };

// "revolute", "prismatic", "ball", "fixed", "mimic".
const char* LoopJointTypeName(LoopJointType type);

// Constraint equations of a cut joint of this type: 6 less the joint's freedoms (a coupling:
// 1).
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
  double multiplier = 1.0;            // kMimic: q(body_b) = multiplier * q(body_a) + offset
  double offset = 0.0;                // kMimic: rad or m, as q(body_b)
};

}  // namespace mbstream
