// Singular poses of a mechanism with closed loops: where the loop constraints and the
// prescribed joints, A = [G (independent rows); E], stop determining the joints (a dead
// centre, a change point where the bars line up, a Delta's rods all parallel). A driven run
// (formulation kinematic) watches A frame by frame: at a pose where A's unit rows are nearly
// dependent, or after a frame step through one (det A changed sign), it stops, saying when
// and at which pose, rather than follow a loop branch the drives no longer choose.
#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>

#include "server/kinematics/row_conditioning.h"
#include "server/model/model.h"

namespace mbstream {

// RowConditioning::Of below which a pose is taken for singular: a frame there stops the run
// (the passive Delta's fall: 0.019 as drawn, 1.9e-3 at t = 0.285 s, 8.8e-6 at 0.2923 s where
// CVODE stalls; docs/closed_loops.md).
inline constexpr double kSingularPoseConditioning = 1e-3;

// "crank_joint = 0.1 rad, slider_joint = 0.05 m, ...": the tree's joint values.
std::string PoseText(const Model& model, const Eigen::VectorXd& q);

class SingularPoseWatch {
 public:
  // For A of `rows` x model.num_dofs(). Allocates here only.
  SingularPoseWatch(const Model& model, Eigen::Index rows);

  // The frame at time t, its pose q and A at q: the message when the mechanism is at a
  // singular pose or went through one since the previous frame, else nullopt (and the frame
  // becomes the previous one). Allocates only for the message.
  std::optional<std::string> Check(double t, const Eigen::VectorXd& q, const Eigen::MatrixXd& A);

 private:
  const Model& model_;
  const bool square_;
  RowConditioning conditioning_;
  Eigen::VectorXd last_q_;
  double last_t_ = 0.0;
  int last_sign_ = 0;  // 0: no previous frame
};

}  // namespace mbstream
