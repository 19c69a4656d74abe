// The viewer's own kinematic chain (it never links the server's physics code).
//
// Frame 0 is the device base, placed in World; frame i+1 belongs to joint i and hangs from
// frame `parent` (< i+1): frame = parent * pre * motion(q) * post, where motion is a
// rotation about `axis` (revolute, q in rad) or a translation along it (prismatic, q in m),
// or for a free joint the pose its seven values give (x y z in m, then the unit quaternion
// qw qx qy qz: motion = translation(x, y, z) * rotation(q), the quaternion normalised), or for
// a ball joint the rotation its four values give (the unit quaternion qw qx qy qz of the child
// in the joint frame, normalised: motion = rotation(q)).
// Fixed joints (URDF) take no joint value. Lengths are metres.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace mbstream::viewer {

enum class ChainJointKind { kRevolute, kPrismatic, kFixed, kFree, kBall };

// The joint values a joint of `kind` takes: 1, 0 (fixed), 7 (free) or 4 (ball).
int ChainJointValues(ChainJointKind kind);

// The names of a free joint's seven values: "NAME.x" ".y" ".z" ".qw" ".qx" ".qy" ".qz".
std::string FreeValueName(const std::string& joint, int value);

// The names of a ball joint's four values: "NAME.qw" ".qx" ".qy" ".qz".
std::string BallValueName(const std::string& joint, int value);

struct ChainJoint {
  std::string name;
  int parent = 0;  // frame number
  Eigen::Isometry3d pre = Eigen::Isometry3d::Identity();
  ChainJointKind kind = ChainJointKind::kRevolute;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit, in the joint frame
  Eigen::Isometry3d post = Eigen::Isometry3d::Identity();
};

class KinematicChain {
 public:
  KinematicChain() = default;
  // Throws InputError when a parent is not an earlier frame or an axis is zero.
  KinematicChain(Eigen::Isometry3d base_in_world, std::vector<ChainJoint> joints);

  int frame_count() const { return static_cast<int>(joints_.size()) + 1; }
  // Number of joint values (one per revolute or prismatic joint, seven per free joint, four
  // per ball joint).
  int dof() const { return static_cast<int>(dof_joints_.size()); }
  const std::vector<ChainJoint>& joints() const { return joints_; }
  // The joint of joint value `i` (a free or ball joint's for each of its values).
  const ChainJoint& dof_joint(int i) const { return joints_[dof_joints_[i]]; }
  const Eigen::Isometry3d& base_in_world() const { return base_in_world_; }

  // Reorders the joint values to follow `names` (the server's joint order): a moving joint's
  // name; for a free or ball joint either its name (its values in their order) or its value
  // names (FreeValueName, BallValueName). Throws InputError naming the joints that differ when
  // `names` are not exactly the moving joints'.
  void OrderJointValuesBy(const std::vector<std::string>& names);

  // Every frame in World for joint values `q` (size dof(), SI). `frames` has frame_count()
  // entries. Allocates nothing.
  void Compute(std::span<const double> q, std::span<Eigen::Isometry3d> frames) const;

 private:
  Eigen::Isometry3d base_in_world_ = Eigen::Isometry3d::Identity();
  std::vector<ChainJoint> joints_;
  std::vector<int> dof_joints_;      // joint index of each joint value
  std::vector<int> value_of_joint_;  // first joint value of each joint, -1 for a fixed joint
};

}  // namespace mbstream::viewer
