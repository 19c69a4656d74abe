// The joint-space formulation of a mechanism with closed loops as the stabilised index-2 DAE
// of Gear, Gupta and Leimkuhler (1985), for IDA. Unknowns y = [q; v; lambda; mu] with
// A = [G (independent rows); E (prescribed joints)] (k rows):
//   q' = v + A^T mu                      (mu: the projection's multiplier, 0 on the solution)
//   M(q) v' + h(q, v) = tau - damping v + A^T lambda
//   A(q) v = [0; qd_ref(t)]              (velocity constraints)
//   [phi(q); q_p] = [0; q_ref(t)]        (position constraints)
// Both the position and the velocity constraints hold to the solver's tolerance, with no
// gain to tune; lambda's prescribed entries are those joints' drive efforts.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "server/drives/drive_set.h"
#include "server/integrate/ida_system.h"
#include "server/kinematics/loop_constraints.h"
#include "server/kinematics/loop_solver.h"
#include "server/kinematics/row_conditioning.h"
#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

class ClosedLoopDae : public DaeSystem {
 public:
  // Keeps references to model, loops and drives. `rank`: the independent rows (PlanLoopRun).
  ClosedLoopDae(const Model& model, const std::vector<LoopClosure>& loops, const DriveSet& drives,
                const LoopRank& rank);

  int size() const override { return 2 * n_ + 2 * k_; }
  int Residual(double t, const double* y, const double* yp, double* r) override;
  void DifferentialIds(double* id) const override;
  // The run's atol for q and v; MultiplierTolerances for lambda and mu.
  void AbsoluteTolerances(double atol, const double* y0, double* atols) const override;
  const std::vector<int>& JacobianColumnStarts() const override { return column_starts_; }
  const std::vector<int>& JacobianRowIndices() const override { return row_indices_; }

  // Consistent (y0, yp0) at t0 from an assembled q0, qd0 (PlanLoopRun): the accelerations and
  // multipliers of the constrained dynamics; mu = 0 and q' = qd0.
  void ConsistentStart(double t0, const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0,
                       Eigen::VectorXd* y0, Eigen::VectorXd* yp0);

  // At y (after an output): the drive efforts (actuator laws; the prescribed joints' lambda)
  // and the constraint residuals, largest |phi| over gap (m) and alignment (rad) rows and of
  // G v. Allocates nothing.
  void Readout(double t, const double* y, Eigen::VectorXd* effort, double* gap, double* alignment,
               double* velocity);
  // After Readout at the same y: the cut joints' reactions (6 per loop,
  // LoopConstraints::Reactions) from lambda's entries of the independent loop rows (M v' + h =
  // tau + A^T lambda, the sign of the ODE's multipliers). Allocates nothing.
  void Reactions(const double* y, Eigen::VectorXd* reactions) const;
  // After Readout at the same y: the power of the loop constraints' forces, lambda^T G v over
  // the independent rows (W; zero to the tolerance, which holds G v = 0). Allocates nothing.
  double ConstraintPower(const double* y) const;
  // At y's pose: RowConditioning::Of A (the independent loop rows and the prescribed joints'),
  // which a singular pose of the mechanism takes to 0 (singular_pose.h). Allocates nothing.
  double ConstraintConditioning(const double* y);

  const Model& model() const { return model_; }

  int num_multipliers() const { return k_; }

 private:
  void Constraints(const Eigen::VectorXd& q);  // BodyKinematics, phi_, G_, A_ at q

  const Model& model_;
  const DriveSet& drives_;
  const int n_;
  const int k_;
  const LoopRank rank_;
  std::vector<int> prescribed_;
  Data data_;
  LoopConstraints constraints_;
  Eigen::VectorXd q_, v_, vp_, lambda_, mu_, tau_, phi_, phi_dot_;
  Eigen::MatrixXd G_, A_;
  RowConditioning conditioning_;  // ConstraintConditioning's workspace
  DriveSet::Workspace drive_workspace_;
  std::vector<int> column_starts_, row_indices_;
};

}  // namespace mbstream
