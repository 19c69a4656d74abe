// Builds a Model link by link, by name, the way a URDF describes it.
//
// The builder checks the structure (unique names, parents defined before children, unit
// axes, physical inertias) and throws InputError with a message naming the link or joint;
// importers check their own input first and so normally never trigger these.
#pragma once

#include <map>
#include <string>

#include "server/model/model.h"

namespace mbstream {

class ModelBuilder {
 public:
  ModelBuilder(std::string model_name, std::string base_link);

  // Adds `link`, moved by `joint` (revolute or prismatic) relative to `parent_link`.
  void AddMovingLink(const std::string& link, const std::string& parent_link, const Joint& joint,
                     const RigidInertia& inertia);

  // Adds `link`, moved by a ball joint named `joint_name` whose frame is X_PJ in
  // `parent_link`: one body turning about the joint frame's origin (JointType::kBall, model.h),
  // its frame the joint frame turned by the joint's quaternion (identity at q = (1, 0, 0, 0)).
  void AddBallLink(const std::string& link, const std::string& parent_link,
                   const std::string& joint_name, const Pose& X_PJ, const RigidInertia& inertia);

  // Adds `link` as a free body: moved by a free joint named `joint_name` (6 degrees of freedom,
  // model.h) relative to the world, at the pose X_WL by default (its q when a run gives no
  // initial_q). A free joint exists only at the root of a tree, as in MuJoCo, hence no parent;
  // children hang from `link` through AddMovingLink, AddBallLink and AddFixedLink as usual.
  // `joint_name` may equal `link` (a model file's free link, which has no joint of its own).
  void AddFreeLink(const std::string& link, const std::string& joint_name, const Pose& X_WL,
                   const RigidInertia& inertia);

  // Adds `link` rigidly attached to `parent_link` at X_PL. Its inertia (which may be zero
  // mass) is merged into the body it hangs from; the link stays available as a frame.
  void AddFixedLink(const std::string& link, const std::string& parent_link, const Pose& X_PL,
                    const RigidInertia& inertia);

  // Adds a named point (probe) fixed in `link` at p_LP (m, in the link frame).
  void AddPoint(const std::string& name, const std::string& link, const Vector3d& p_LP);

  // Declares which frame is the tool centre point.
  void SetTcp(const std::string& frame_name);

  void SetGravity(const Vector3d& gravity) { model_.gravity = gravity; }

  // Returns the finished model. The builder must not be used afterwards.
  Model Build();

 private:
  // Where a named link is: the body it moves with and its pose in that body.
  struct LinkPlace {
    int body;
    Pose X_BL;
  };
  const LinkPlace& PlaceOf(const std::string& link, const std::string& context) const;
  void CheckNewName(const std::string& link) const;
  // AddMovingLink's and AddBallLink's work.
  void AddBody(const std::string& link, const std::string& parent_link, const Joint& joint,
               const RigidInertia& inertia);

  Model model_;
  std::map<std::string, LinkPlace> links_;
  std::map<std::string, int> names_;
};

// Throws InputError unless `inertia` is physical: finite positive mass, symmetric positive
// definite rotational inertia satisfying the triangle inequality. `what` names the link.
void ValidateRigidInertia(const RigidInertia& inertia, const std::string& what);

}  // namespace mbstream
