// The order of a URDF's joints, which is the model's degree-of-freedom order (the order of
// q on the wire): document order, except that a joint waits until its parent link is
// placed; each step takes the first joint, from the front of the document, whose parent is
// placed. A file that lists parents first keeps its order.
#pragma once

#include <string>
#include <vector>

#include <urdf_model/model.h>

namespace mbstream::model_files {

struct JointOrder {
  std::vector<urdf::JointConstSharedPtr> ordered;   // every joint, fixed ones included
  std::vector<urdf::JointConstSharedPtr> unplaced;  // joints not connected to the root (loops)
};

// `document_order` names every joint of `model` (UrdfOutline::joint_order); names urdfdom
// does not know are skipped.
JointOrder OrderJoints(const urdf::ModelInterface& model,
                       const std::vector<std::string>& document_order);

// The names of the moving (non-fixed) joints of `order`, in order.
std::vector<std::string> MovingJointNames(const JointOrder& order);

}  // namespace mbstream::model_files
