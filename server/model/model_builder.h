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

  // Adds `link`, moved by a ball joint named `joint_name` (at `where` in the model file) whose
  // frame is X_PJ in `parent_link`: three revolute bodies through the joint's centre, about
  // its x, y and z axes in turn (ball_joint.h), named axis_names[0..2] (the joints; the first
  // two massless links take the same names), the last carrying `link` and its inertia.
  void AddBallLink(const std::string& link, const std::string& parent_link,
                   const std::string& joint_name, const std::string& where, const Pose& X_PJ,
                   const std::string (&axis_names)[3], const RigidInertia& inertia);

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
  // AddMovingLink's work; `massless`: no inertia of its own (a ball joint's inner links).
  void AddBody(const std::string& link, const std::string& parent_link, const Joint& joint,
               const RigidInertia& inertia, bool massless);

  Model model_;
  std::map<std::string, LinkPlace> links_;
  std::map<std::string, int> names_;
};

// Throws InputError unless `inertia` is physical: finite positive mass, symmetric positive
// definite rotational inertia satisfying the triangle inequality. `what` names the link.
void ValidateRigidInertia(const RigidInertia& inertia, const std::string& what);

}  // namespace mbstream
