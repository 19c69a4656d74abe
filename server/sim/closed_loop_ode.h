// The joint-space formulation of a mechanism with closed loops: the tree's coordinates
// y = [q; qd] (2n states) with the loops' constraints phi(q) = 0 (and the prescribed joints'
// q_i = q_ref(t)) held by Lagrange multipliers,
//   M qdd + h(q, qd) = tau - damping qd + A^T mu,   A = [G (independent rows); E (prescribed)]
//   A qdd = -bias - alpha A qd' - beta c            (Baumgarte: c'' + alpha c' + beta c = 0)
// an ODE whose drift the Baumgarte terms damp and the projection (ManifoldProjection, after
// each step of CVODE BDF) removes: positions by minimal-norm Newton onto phi = 0, velocities
// onto G qd = 0. The prescribed joints' drive efforts are their multipliers.
#pragma once

#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "server/body/baumgarte_parameters.h"
#include "server/drives/drive_set.h"
#include "server/integrate/manifold_projection.h"
#include "server/integrate/ode_system.h"
#include "server/kinematics/loop_constraints.h"
#include "server/kinematics/loop_solver.h"
#include "server/kinematics/row_conditioning.h"
#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

class ClosedLoopOde : public OdeSystem, public ManifoldProjection {
 public:
  // Keeps references to model, loops and drives, which must outlive it. `q_assembled`
  // satisfies the constraints: the independent rows are chosen there (LoopSolver::Analyse).
  // `projection_tolerance`: the Newton tolerance of Project (m or rad).
  ClosedLoopOde(const Model& model, const std::vector<LoopClosure>& loops, const DriveSet& drives,
                const Eigen::VectorXd& q_assembled, const BaumgarteParameters& gains,
                double projection_tolerance);

  int size() const override { return 2 * n_; }
  int num_positions() const override { return n_; }
  int Rhs(double t, const double* y, double* ydot) override;
  int Project(double t, const double* y, double* correction) override;

  // Evaluates the mechanism at (t, y): q(), qd(), qdd(), drive_effort() (the actuators'
  // laws, and the prescribed joints' multipliers). False when the constraint system is
  // singular or a value is not finite. Allocates nothing.
  bool Evaluate(double t, const double* y);
  // The constraint residuals at the last Evaluate: largest |phi| over gap rows (m) and
  // alignment rows (rad), and of G qd (m/s or rad/s).
  void Residuals(double* gap, double* alignment, double* velocity) const;
  // After Evaluate: how far the constraint rows A (the independent rows of G, then the
  // prescribed joints' rows), each scaled to unit length, are from singular: their smallest
  // singular value over their largest (1: orthogonal rows; 0: a singular configuration of
  // the mechanism, or of the tree's coordinates, where the multipliers are undefined and
  // the ODE has no solution through it). Allocates nothing.
  double ConstraintConditioning();
  // After Evaluate: the power of the loop constraints' forces G^T mu on the tree, mu^T G qd
  // over the independent rows (W): zero where the velocity constraints hold, and the work the
  // Baumgarte terms do where they do not (the energy balance counts it). The prescribed
  // joints' rows are their drive efforts. Allocates nothing.
  double ConstraintPower() const;
  // After Evaluate: the cut joints' reactions from the multipliers (6 per loop:
  // LoopConstraints::Reactions). Allocates nothing.
  void Reactions(Eigen::VectorXd* reactions) const {
    constraints_.Reactions(data_, rank_.independent, mu_, *reactions);
  }

  const LoopRank& rank() const { return rank_; }
  const Model& model() const { return model_; }
  const Eigen::VectorXd& q() const { return q_; }
  const Eigen::VectorXd& qd() const { return qd_; }
  const Eigen::VectorXd& qdd() const { return qdd_; }
  const Eigen::VectorXd& drive_effort() const { return effort_; }
  Data& data() { return data_; }

 private:
  void HeldValues(double t);  // the prescribed joints' references at t into held_*

  const Model& model_;
  const DriveSet& drives_;
  const int n_;
  const BaumgarteParameters gains_;
  const double projection_tolerance_;
  Data data_;
  LoopConstraints constraints_;
  LoopSolver solver_;
  LoopRank rank_;
  std::vector<int> prescribed_;
  Eigen::VectorXd q_, qd_, qdd_, effort_, force_, minv_force_;
  Eigen::VectorXd held_q_, held_qd_, held_qdd_;
  Eigen::VectorXd phi_, phi_dot_, bias_, b_, mu_;
  Eigen::MatrixXd G_, A_, Y_, S_;
  Eigen::LLT<Eigen::MatrixXd> mass_llt_, s_llt_;
  RowConditioning conditioning_{0, 0};  // ConstraintConditioning's workspace
  DriveSet::Workspace drive_workspace_;
};

}  // namespace mbstream
