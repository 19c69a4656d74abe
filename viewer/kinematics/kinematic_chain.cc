#include "viewer/kinematics/kinematic_chain.h"

#include <cassert>
#include <map>
#include <set>
#include <stdexcept>

#include "shared/common/check.h"

namespace mbstream::viewer {

namespace {

constexpr int kFreeValues = 7;
constexpr const char* kFreeSuffix[kFreeValues] = {".x", ".y", ".z", ".qw", ".qx", ".qy", ".qz"};
constexpr int kBallValues = 4;
constexpr const char* kBallSuffix[kBallValues] = {".qw", ".qx", ".qy", ".qz"};

// The name of value `v` of a joint with several.
std::string ValueName(const ChainJoint& joint, int v) {
  return joint.kind == ChainJointKind::kFree ? FreeValueName(joint.name, v)
                                             : BallValueName(joint.name, v);
}

// The rotation of the quaternion q[0..3] (qw qx qy qz), normalised; none for a zero one.
Eigen::Matrix3d QuaternionRotation(const double* q) {
  Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
  const double norm = rotation.norm();
  if (!(norm > 1e-12)) return Eigen::Matrix3d::Identity();  // no rotation to show (NaN-free)
  rotation.coeffs() /= norm;
  return rotation.toRotationMatrix();
}

}  // namespace

int ChainJointValues(ChainJointKind kind) {
  switch (kind) {
    case ChainJointKind::kFixed:
      return 0;
    case ChainJointKind::kFree:
      return kFreeValues;
    case ChainJointKind::kBall:
      return kBallValues;
    default:
      return 1;
  }
}

std::string FreeValueName(const std::string& joint, int value) {
  MBSTREAM_CHECK(value >= 0 && value < kFreeValues);
  return joint + kFreeSuffix[value];
}

std::string BallValueName(const std::string& joint, int value) {
  MBSTREAM_CHECK(value >= 0 && value < kBallValues);
  return joint + kBallSuffix[value];
}

KinematicChain::KinematicChain(Eigen::Isometry3d base_in_world, std::vector<ChainJoint> joints)
    : base_in_world_(base_in_world), joints_(std::move(joints)) {
  for (size_t i = 0; i < joints_.size(); ++i) {
    ChainJoint& joint = joints_[i];
    if (joint.parent < 0 || joint.parent > static_cast<int>(i)) {
      throw InputError("joint '" + joint.name + "' hangs from frame " +
                       std::to_string(joint.parent) + ", which is not an earlier frame");
    }
    if (joint.kind == ChainJointKind::kRevolute || joint.kind == ChainJointKind::kPrismatic) {
      const double norm = joint.axis.norm();
      if (!(norm > 1e-12)) {
        throw InputError("joint '" + joint.name + "' has a zero axis");
      }
      joint.axis /= norm;
    }
    const int values = ChainJointValues(joint.kind);
    value_of_joint_.push_back(values == 0 ? -1 : static_cast<int>(dof_joints_.size()));
    for (int v = 0; v < values; ++v) dof_joints_.push_back(static_cast<int>(i));
  }
}

void KinematicChain::OrderJointValuesBy(const std::vector<std::string>& names) {
  // Every joint value by name, and each free or ball joint's values by the joint's name.
  std::map<std::string, std::vector<int>> values_of_name;  // values in the current order
  std::map<std::string, std::string> joint_of_name;
  for (size_t i = 0; i < joints_.size(); ++i) {
    const ChainJoint& joint = joints_[i];
    const int first = value_of_joint_[i];
    if (first < 0) continue;
    if (const int values = ChainJointValues(joint.kind); values > 1) {
      std::vector<int>& all = values_of_name[joint.name];
      for (int v = 0; v < values; ++v) {
        values_of_name[ValueName(joint, v)] = {first + v};
        joint_of_name[ValueName(joint, v)] = joint.name;
        all.push_back(first + v);
      }
    } else {
      values_of_name[joint.name] = {first};
    }
    joint_of_name[joint.name] = joint.name;
  }
  std::string missing, extra;
  std::vector<int> order;  // the old value index of each new value
  std::set<int> seen;
  for (const std::string& name : names) {
    const auto it = values_of_name.find(name);
    bool fresh = it != values_of_name.end();
    if (fresh) {
      for (const int value : it->second) fresh = fresh && seen.count(value) == 0;
    }
    if (!fresh) {
      extra += (extra.empty() ? "'" : ", '") + name + "'";
      continue;
    }
    for (const int value : it->second) {
      seen.insert(value);
      order.push_back(value);
    }
  }
  std::set<std::string> missing_joints;
  for (int value = 0; value < dof(); ++value) {
    if (seen.count(value) == 0) missing_joints.insert(joints_[dof_joints_[value]].name);
  }
  for (const std::string& name : missing_joints) {
    missing += (missing.empty() ? "'" : ", '") + name + "'";
  }
  if (!missing.empty() || !extra.empty()) {
    std::string message = "the joint names differ:";
    if (!extra.empty()) message += " the model's " + extra + " not in the scene;";
    if (!missing.empty()) message += " the scene's " + missing + " not in the model;";
    message.pop_back();
    throw InputError(message);
  }
  // A free or ball joint's values stay together, in their order: the server names them so.
  std::vector<int> new_of_old(dof());
  for (size_t value = 0; value < order.size(); ++value) new_of_old[order[value]] = value;
  std::vector<int> dof_joints(dof());
  std::vector<int> value_of_joint = value_of_joint_;  // the chain unchanged when this throws
  for (size_t i = 0; i < joints_.size(); ++i) {
    const int first = value_of_joint_[i];
    if (first < 0) continue;
    const int values = ChainJointValues(joints_[i].kind);
    for (int v = 1; v < values; ++v) {
      if (new_of_old[first + v] != new_of_old[first] + v) {
        const bool free = joints_[i].kind == ChainJointKind::kFree;
        throw InputError(std::string("the joint names differ: ") + (free ? "free" : "ball") +
                         " joint '" + joints_[i].name + "' has its " + (free ? "seven" : "four") +
                         " values apart or out of order in the model");
      }
    }
    value_of_joint[i] = new_of_old[first];
    for (int v = 0; v < values; ++v) dof_joints[new_of_old[first] + v] = static_cast<int>(i);
  }
  value_of_joint_ = std::move(value_of_joint);
  dof_joints_ = std::move(dof_joints);
}

void KinematicChain::Compute(std::span<const double> q, std::span<Eigen::Isometry3d> frames) const {
  assert(static_cast<int>(q.size()) == dof());
  assert(static_cast<int>(frames.size()) == frame_count());
  frames[0] = base_in_world_;
  for (size_t i = 0; i < joints_.size(); ++i) {
    const ChainJoint& joint = joints_[i];
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    const int v = value_of_joint_[i];
    if (joint.kind == ChainJointKind::kRevolute) {
      motion.linear() = Eigen::AngleAxisd(q[v], joint.axis).toRotationMatrix();
    } else if (joint.kind == ChainJointKind::kPrismatic) {
      motion.translation() = joint.axis * q[v];
    } else if (joint.kind == ChainJointKind::kFree) {
      motion.linear() = QuaternionRotation(&q[v + 3]);
      motion.translation() = Eigen::Vector3d(q[v], q[v + 1], q[v + 2]);
    } else if (joint.kind == ChainJointKind::kBall) {
      motion.linear() = QuaternionRotation(&q[v]);
    }
    frames[i + 1] = frames[joint.parent] * joint.pre * motion * joint.post;
  }
}

}  // namespace mbstream::viewer
