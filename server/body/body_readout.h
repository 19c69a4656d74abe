// What a run reports from a body-coordinate state: joint angles and rates (read off the
// relative poses of neighbouring bodies), the TCP from the last body's pose, drive efforts
// (the drive constraints' multipliers of the acceleration-level solve), energies, and the
// constraint drift.
#pragma once

#include <Eigen/Core>

#include "server/body/body_mechanics.h"
#include "server/body/body_model.h"
#include "server/drives/drive_set.h"

namespace mbstream {

// The largest constraint violations seen so far.
struct ConstraintDrift {
  double position = 0.0;         // m: |g| of the joint-point rows
  double orientation = 0.0;      // rad (small angles): |g| of the axis and drive rows
  double velocity = 0.0;         // m/s or rad/s: |G nu + g_t|
  double quaternion_norm = 0.0;  // | |e| - 1 |
};

class BodyReadout {
 public:
  // Keeps references to its arguments, which must outlive it.
  BodyReadout(const BodyModel& body_model, const DriveSet& drives);

  // Reads the state y (its first 13n entries) at t. Joint angles continue the previous
  // call's branch (the first call starts from `q_start`). With `efforts`, solves for the
  // prescribed joints' drive efforts. Returns false if anything is not finite. Allocates
  // nothing.
  bool Read(double t, const double* y, bool efforts);
  void SetStart(const Eigen::VectorXd& q_start) { q_ = q_start; }
  // The run's contact (BodyMechanics::UseContact): Read then evaluates the contacts at y, and
  // `forces`' contacts() are those of the state read. Allocates; call before the run.
  void UseContact(ContactForces* forces) { mechanics_.UseContact(forces); }

  const Eigen::VectorXd& q() const { return q_; }
  const Eigen::VectorXd& qd() const { return qd_; }
  const Eigen::VectorXd& effort() const { return effort_; }
  const Vector3d& tcp() const { return tcp_; }
  double kinetic() const { return kinetic_; }
  double potential() const { return potential_; }
  const ConstraintDrift& drift() const { return drift_; }

  // After Read(..., efforts = true): the cut joints' reactions from the multipliers of their
  // kept rows, 6 per cut joint in BodyModel::cuts' order (RunResult::loop_forces): the force
  // (N) and the torque (N*m, about the joint point) that the joint's parent side exerts on its
  // child side, base frame. What only dropped rows would carry is 0. Allocates nothing.
  void CutReactions(Eigen::Ref<Eigen::VectorXd> reactions) const;

 private:
  const BodyModel& bm_;
  BodyMechanics mechanics_;
  Eigen::VectorXd q_, qd_, effort_;
  Vector3d tcp_ = Vector3d::Zero();
  double kinetic_ = 0.0, potential_ = 0.0;
  ConstraintDrift drift_;
};

}  // namespace mbstream
