// Appends a run's output frames to its RunResult: TCP, energies, and the accuracy figures
// (TCP against direct kinematics of the prescribed motion, energy balance).
#pragma once

#include <Eigen/Core>

#include "server/drives/drive_set.h"
#include "server/kinematics/loop_coordinates.h"
#include "server/model/data.h"
#include "server/model/model.h"
#include "server/sim/run_result.h"

namespace mbstream {

// What a formulation that has them computes itself instead of the recorder (the body
// formulations: TCP from the last body's pose, energies from the bodies' states).
struct FrameExtras {
  Vector3d tcp = Vector3d::Zero();
  double kinetic = 0.0;    // J
  double potential = 0.0;  // J
};

class FrameRecorder {
 public:
  // track_tcp_error: compare the TCP with direct kinematics of the prescribed motion (off
  // when the states are that motion, as in the kinematic formulation: the error is 0; off with
  // free or ball joints, whose references are poses, not coordinates).
  // latest_only: keep only the latest frame in `result` (see RunResult::first_seq).
  FrameRecorder(const Model& model, const DriveSet& drives, RunResult& result, size_t frames,
                bool track_tcp_error, bool latest_only = false);

  // Records a frame; `effort` (drive efforts) may be null when torques are not reported
  // and no work is tracked; `extras`, if given, replaces the TCP and energies that would be
  // computed from (q, qd). Returns false, recording nothing, if any value is not finite.
  bool Record(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
              const Eigen::VectorXd* effort, const FrameExtras* extras = nullptr);

  // The formulation integrates the work of drives and damping itself (a quadrature of its
  // ODE): the energy balance then uses the value given by SetWork before each Record
  // instead of the trapezoid rule over the output frames. Call before the first frame.
  void UseIntegratedWork();
  void SetWork(double work) { work_ = work; }
  // A mechanism with closed loops: the power of the loop constraints' forces at the next
  // Record (the multipliers' lambda^T G qd, zero when the velocity constraints hold exactly),
  // counted with the drives' in the work of the energy balance. Call before each Record.
  void SetConstraintPower(double power) { constraint_power_ = power; }

  // A mechanism with closed loops: each frame's q and qd gain the cut joints' coordinates
  // and rates (loop_coordinates.h) after the tree's, its efforts as many zeros (a cut joint
  // has no drive). `result.num_dofs` counts them. Call before the first frame; `coordinates`
  // must outlive the recorder.
  void AppendLoopCoordinates(LoopCoordinates* coordinates);
  // Each frame also records `forces` (6 per cut joint: RunResult::loop_forces), as the frame
  // source left them before Record. Call before the first frame; `forces` must outlive the
  // recorder.
  void AppendLoopForces(const Eigen::VectorXd* forces);

  const Model& model() const { return model_; }

 private:
  void TrackEnergy(double t, double energy, const Eigen::VectorXd& qd,
                   const Eigen::VectorXd* effort);
  void TrackTcpError(double t, const Vector3d& tcp);

  const Model& model_;
  const DriveSet& drives_;
  RunResult& result_;
  Data data_;
  Eigen::VectorXd q_ref_;
  const bool track_tcp_error_;
  const bool latest_only_;
  bool integrated_work_ = false;
  LoopCoordinates* loop_coordinates_ = nullptr;
  Eigen::VectorXd loop_value_, loop_rate_, loop_effort_;
  const Eigen::VectorXd* loop_forces_ = nullptr;
  double energy0_ = 0.0, work_ = 0.0, last_power_ = 0.0, last_t_ = 0.0, scale_ = 0.0;
  double constraint_power_ = 0.0;
  // The trapezoid rule over every other frame (frames 0, 2, 4, ...), for the estimate of the
  // rule's error (RunStats::energy_quadrature_error_max): its work, the power and time at
  // the start of its current interval, and the frames since the first.
  double coarse_work_ = 0.0, power2_ = 0.0, t2_ = 0.0;
  long energy_frames_ = 0;
};

}  // namespace mbstream
