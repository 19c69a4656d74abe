#include "viewer/kinematics/kinematic_chain.h"

#include <cassert>
#include <map>
#include <set>
#include <stdexcept>

#include "common/check.h"

namespace mbstream::viewer {

KinematicChain::KinematicChain(Eigen::Isometry3d base_in_world, std::vector<ChainJoint> joints)
    : base_in_world_(base_in_world), joints_(std::move(joints)) {
  for (size_t i = 0; i < joints_.size(); ++i) {
    ChainJoint& joint = joints_[i];
    if (joint.parent < 0 || joint.parent > static_cast<int>(i)) {
      throw InputError("joint '" + joint.name + "' hangs from frame " +
                       std::to_string(joint.parent) + ", which is not an earlier frame");
    }
    if (joint.kind != ChainJointKind::kFixed) {
      const double norm = joint.axis.norm();
      if (!(norm > 1e-12)) {
        throw InputError("joint '" + joint.name + "' has a zero axis");
      }
      joint.axis /= norm;
      value_of_joint_.push_back(static_cast<int>(dof_joints_.size()));
      dof_joints_.push_back(static_cast<int>(i));
    } else {
      value_of_joint_.push_back(-1);
    }
  }
}

void KinematicChain::OrderJointValuesBy(const std::vector<std::string>& names) {
  std::map<std::string, int> joint_of_name;
  for (int index : dof_joints_) joint_of_name[joints_[index].name] = index;
  std::string missing, extra;
  std::vector<int> order;
  std::set<std::string> seen;
  for (const std::string& name : names) {
    const auto it = joint_of_name.find(name);
    if (it == joint_of_name.end() || !seen.insert(name).second) {
      extra += (extra.empty() ? "'" : ", '") + name + "'";
    } else {
      order.push_back(it->second);
    }
  }
  for (const auto& [name, index] : joint_of_name) {
    if (seen.count(name) == 0) missing += (missing.empty() ? "'" : ", '") + name + "'";
  }
  if (!missing.empty() || !extra.empty()) {
    std::string message = "the joint names differ:";
    if (!extra.empty()) message += " the model's " + extra + " not in the scene;";
    if (!missing.empty()) message += " the scene's " + missing + " not in the model;";
    message.pop_back();
    throw InputError(message);
  }
  dof_joints_ = std::move(order);
  for (size_t value = 0; value < dof_joints_.size(); ++value) {
    value_of_joint_[dof_joints_[value]] = static_cast<int>(value);
  }
}

void KinematicChain::Compute(std::span<const double> q, std::span<Eigen::Isometry3d> frames) const {
  assert(static_cast<int>(q.size()) == dof());
  assert(static_cast<int>(frames.size()) == frame_count());
  frames[0] = base_in_world_;
  for (size_t i = 0; i < joints_.size(); ++i) {
    const ChainJoint& joint = joints_[i];
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (joint.kind == ChainJointKind::kRevolute) {
      motion.linear() = Eigen::AngleAxisd(q[value_of_joint_[i]], joint.axis).toRotationMatrix();
    } else if (joint.kind == ChainJointKind::kPrismatic) {
      motion.translation() = joint.axis * q[value_of_joint_[i]];
    }
    frames[i + 1] = frames[joint.parent] * joint.pre * motion * joint.post;
  }
}

}  // namespace mbstream::viewer
