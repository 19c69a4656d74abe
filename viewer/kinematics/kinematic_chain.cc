#include "viewer/kinematics/kinematic_chain.h"

#include <cassert>
#include <stdexcept>

namespace mbstream::viewer {

KinematicChain::KinematicChain(Eigen::Isometry3d base_in_world, std::vector<ChainJoint> joints)
    : base_in_world_(base_in_world), joints_(std::move(joints)) {
  for (size_t i = 0; i < joints_.size(); ++i) {
    ChainJoint& joint = joints_[i];
    if (joint.parent < 0 || joint.parent > static_cast<int>(i)) {
      throw std::invalid_argument("joint '" + joint.name + "' hangs from frame " +
                                  std::to_string(joint.parent) + ", which is not an earlier frame");
    }
    if (joint.kind != ChainJointKind::kFixed) {
      const double norm = joint.axis.norm();
      if (!(norm > 1e-12)) {
        throw std::invalid_argument("joint '" + joint.name + "' has a zero axis");
      }
      joint.axis /= norm;
      dof_joints_.push_back(static_cast<int>(i));
    }
  }
}

void KinematicChain::Compute(std::span<const double> q, std::span<Eigen::Isometry3d> frames) const {
  assert(static_cast<int>(q.size()) == dof());
  assert(static_cast<int>(frames.size()) == frame_count());
  frames[0] = base_in_world_;
  size_t value = 0;
  for (size_t i = 0; i < joints_.size(); ++i) {
    const ChainJoint& joint = joints_[i];
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (joint.kind == ChainJointKind::kRevolute) {
      motion.linear() = Eigen::AngleAxisd(q[value++], joint.axis).toRotationMatrix();
    } else if (joint.kind == ChainJointKind::kPrismatic) {
      motion.translation() = joint.axis * q[value++];
    }
    frames[i + 1] = frames[joint.parent] * joint.pre * motion * joint.post;
  }
}

}  // namespace mbstream::viewer
