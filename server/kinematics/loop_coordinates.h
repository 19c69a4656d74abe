// The cut joints' own coordinates, computed from the tree's state: what a results file
// shows for a loop-closing joint beside the tree's joints (joints.csv, velocities.csv).
//
// A cut joint's frames A (parent side) and B (child side) coincide at the file's zero pose
// (server/model/loop_closure.h), so each coordinate is 0 there, as for a tree joint:
// - revolute: the angle of B about the axis from A (rad), continued across +-pi from one
//   call to the next (a crank that turns keeps counting), and its rate (rad/s);
// - prismatic: B's displacement along the axis from A (m), and its rate (m/s);
// - ball: three columns, the rotation vector of B in A (rad, |r| <= pi), and B's angular
//   velocity relative to A in A (rad/s: not the rotation vector's derivative);
// - fixed, and a coupling (mimic: its follower is a tree joint): no column.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "server/model/data.h"
#include "server/model/loop_closure.h"
#include "server/model/model.h"

namespace mbstream {

// The coordinates' names, in loop order: the joint's name, and NAME.x, NAME.y, NAME.z for a
// ball joint.
std::vector<std::string> LoopCoordinateNames(const std::vector<LoopClosure>& loops);

// The workspace is allocated once; Compute allocates nothing. Keeps references to model and
// loops.
class LoopCoordinates {
 public:
  LoopCoordinates(const Model& model, const std::vector<LoopClosure>& loops);

  int size() const { return size_; }

  // The coordinates and their rates at tree state (q, qd: nq and nv values, model.h); `value`
  // and `rate` have size().
  // Revolute angles continue from the previous call's (the first call: within +-pi).
  void Compute(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::VectorXd* value,
               Eigen::VectorXd* rate);

 private:
  void Velocities(const Eigen::VectorXd& qd);

  const Model& model_;
  const std::vector<LoopClosure>& loops_;
  int size_ = 0;
  Data data_;
  std::vector<Vector3d> w_, v_;  // bodies' angular velocity and origin velocity, world
  std::vector<double> last_angle_;
  bool first_ = true;
};

}  // namespace mbstream
