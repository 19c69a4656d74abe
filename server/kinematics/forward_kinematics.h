// Forward kinematics: the pose of every body and frame in the base (world) frame.
#pragma once

#include <Eigen/Core>

#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

// Fills data.X_parent, data.X_world and data.frame_world for joint positions q
// (model.nq() values: rad or m, a free body's pose as model.h says). Allocates nothing.
void ForwardKinematics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q);

// Position of frame `frame` in the world frame (m); ForwardKinematics must have run.
inline const Vector3d& FramePosition(const Data& data, int frame) {
  return data.frame_world[frame].p;
}

// The bodies' part of ForwardKinematics: data.X_parent and data.X_world, not
// data.frame_world (for callers that need one or two frames: see FramePositionFromBodies).
// Allocates nothing.
void BodyKinematics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q);

// Position of frame `frame` in the world frame (m) from the bodies' poses, after
// BodyKinematics or ForwardKinematics: FramePosition's value, bit for bit, without the
// frame's orientation.
inline Vector3d FramePositionFromBodies(const Model& model, const Data& data, int frame) {
  const Frame& f = model.frames[frame];
  if (f.body == kBase) return f.X_BF.p;
  const Pose& X_WB = data.X_world[f.body];
  return X_WB.R * f.X_BF.p + X_WB.p;  // as (X_WB * X_BF).p
}

}  // namespace mbstream
