#include "shared/model_files/joint_order.h"

#include <algorithm>
#include <set>

namespace mbstream::model_files {

JointOrder OrderJoints(const urdf::ModelInterface& model,
                       const std::vector<std::string>& document_order) {
  JointOrder order;
  if (model.getRoot() == nullptr) return order;
  std::set<std::string> placed = {model.getRoot()->name};
  std::vector<urdf::JointConstSharedPtr> pending;
  for (const std::string& name : document_order) {
    if (urdf::JointConstSharedPtr joint = model.getJoint(name)) pending.push_back(joint);
  }
  while (!pending.empty()) {
    const auto ready = std::find_if(pending.begin(), pending.end(), [&](const auto& joint) {
      return placed.count(joint->parent_link_name) != 0;
    });
    if (ready == pending.end()) break;
    placed.insert((*ready)->child_link_name);
    order.ordered.push_back(*ready);
    pending.erase(ready);
  }
  order.unplaced = std::move(pending);
  return order;
}

std::vector<std::string> MovingJointNames(const JointOrder& order) {
  std::vector<std::string> names;
  for (const auto& joint : order.ordered) {
    if (joint->type != urdf::Joint::FIXED) names.push_back(joint->name);
  }
  return names;
}

}  // namespace mbstream::model_files
