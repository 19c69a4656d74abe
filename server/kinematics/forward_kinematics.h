// Forward kinematics: the pose of every body and frame in the base (world) frame.
#pragma once

#include <Eigen/Core>

#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

// Fills data.X_parent, data.X_world and data.frame_world for joint positions q
// (size num_dofs; rad or m). Allocates nothing.
void ForwardKinematics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q);

// Position of frame `frame` in the world frame (m); ForwardKinematics must have run.
inline const Vector3d& FramePosition(const Data& data, int frame) {
  return data.frame_world[frame].p;
}

}  // namespace mbstream
