#include "server/model/joint.h"

namespace mbstream {

const char* JointTypeName(JointType type) {
  switch (type) {
    case JointType::kRevolute:
      return "revolute";
    case JointType::kPrismatic:
      return "prismatic";
  }
  return "unknown";
}

}  // namespace mbstream
