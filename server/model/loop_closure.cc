#include "server/model/loop_closure.h"

namespace mbstream {

const char* LoopJointTypeName(LoopJointType type) {
  switch (type) {
    case LoopJointType::kRevolute:
      return "revolute";
    case LoopJointType::kPrismatic:
      return "prismatic";
    case LoopJointType::kBall:
      return "ball";
    case LoopJointType::kFixed:
      return "fixed";
    case LoopJointType::kMimic:
      return "mimic";
  }
  return "?";
}

int LoopJointEquations(LoopJointType type) {
  switch (type) {
    case LoopJointType::kRevolute:
    case LoopJointType::kPrismatic:
      return 5;
    case LoopJointType::kBall:
      return 3;
    case LoopJointType::kFixed:
      return 6;
    case LoopJointType::kMimic:
      return 1;
  }
  return 0;
}

}  // namespace mbstream
