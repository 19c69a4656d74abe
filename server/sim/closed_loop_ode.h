// The joint-space formulation of a mechanism with closed loops: the tree's coordinates
// y = [q; qd] (2n states) with the loops' constraints phi(q) = 0 (and the prescribed joints'
// q_i = q_ref(t)) held by Lagrange multipliers,
//   M qdd + h(q, qd) = tau - damping qd + A^T mu,   A = [G (independent rows); E (prescribed)]
//   A qdd = -bias - alpha A qd' - beta c            (Baumgarte: c'' + alpha c' + beta c = 0)
// an ODE whose drift the Baumgarte terms damp and the projection (ManifoldProjection, after
// each step of CVODE BDF) removes: positions by minimal-norm Newton onto phi = 0, velocities
// onto G qd = 0. The prescribed joints' drive efforts are their multipliers.
//
// With free bodies or ball joints in the tree (model.h) y = [q (nq); qd (nv)], q' = G(q) qd,
// the constraint Jacobian G has nv columns and the projection's Newton steps move q on its
// manifold (StepPositions, coordinate_step.h); the right-hand side and the outputs read every
// quaternion normalised, and every one-step method (ARKODE, RK4, semi-implicit Euler)
// normalises them after each step (ProjectInPlace; the loops there are held by Baumgarte, as
// without quaternions); BDF's projection normalises them too.
#pragma once

#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "server/body/baumgarte_parameters.h"
#include "server/contact/contact_forces.h"
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
  // `projection_tolerance`: the Newton tolerance of Project (m or rad). `contact`, when given
  // (not owned, outlives it), adds the contact forces at every evaluation, and the ODE then
  // integrates the work of the drives, the damping, the loops' and the contacts' forces as a
  // quadrature (an impact between two frames is in it; the trapezoid rule over the frames
  // would miss it).
  ClosedLoopOde(const Model& model, const std::vector<LoopClosure>& loops, const DriveSet& drives,
                const Eigen::VectorXd& q_assembled, const BaumgarteParameters& gains,
                double projection_tolerance, ContactForces* contact = nullptr);

  int size() const override { return nq_ + n_; }
  int num_positions() const override { return nq_; }
  int num_velocities() const override { return n_; }
  // q' = G(q) qd: qd itself without quaternions.
  void PositionRate(const double* q, const double* qd, double* q_rate) override;
  // With quaternions: every one-step method normalises them after each step.
  bool ProjectsEveryMethod() const override { return quaternions_; }
  int ProjectInPlace(double t, double* y) override;
  int Rhs(double t, const double* y, double* ydot) override;
  int Project(double t, const double* y, double* correction) override;
  // With contact: the signed distances of the contact's root pairs
  // (ContactForces::SignedDistances). Allocates nothing.
  int num_roots() const override { return contact_ != nullptr ? contact_->num_root_pairs() : 0; }
  int Roots(double t, const double* y, double* g) override;
  // With contact: two quadratures, the power of the drives, the damping, the loops' and the
  // contacts' forces (W), and the power the contacts dissipate (ContactForces::
  // dissipated_power). Allocates nothing.
  int num_quadratures() const override { return contact_ != nullptr ? 2 : 0; }
  int Quadrature(double t, const double* y, double* qdot) override;
  int RhsAndQuadrature(double t, const double* y, double* ydot, double* qdot) override;

  // Evaluates the mechanism at (t, y): q() (its quaternions normalised), qd(), qdd(),
  // drive_effort() (the actuators' laws, and the prescribed joints' multipliers). False when the
  // constraint system is singular or a value is not finite. Allocates nothing.
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

  // The largest | |quat| - 1 | of y's quaternions (0 without): the integrator's drift from
  // unit length before Evaluate normalises them.
  double QuaternionNormError(const double* y) const;

  const LoopRank& rank() const { return rank_; }
  const Model& model() const { return model_; }
  const Eigen::VectorXd& q() const { return q_; }
  const Eigen::VectorXd& qd() const { return qd_; }
  const Eigen::VectorXd& qdd() const { return qdd_; }
  const Eigen::VectorXd& drive_effort() const { return effort_; }
  Data& data() { return data_; }
  // The contacts of the last evaluation (null without contact).
  const ContactForces* contact() const { return contact_; }
  // The generalised contact forces of the last evaluation (zeros without contact).
  const Eigen::VectorXd& contact_force() const { return contact_tau_; }
  // After Evaluate: the contact forces' power contact_force()^T qd (W; 0 without contact).
  double ContactPower() const { return contact_tau_.dot(qd_); }

 private:
  void HeldValues(double t);  // the prescribed joints' references at t into held_*
  double Power() const;       // the quadrature's integrand after Evaluate

  const Model& model_;
  const DriveSet& drives_;
  const int n_;                    // velocity coordinates (nv)
  const int nq_;                   // position coordinates (nq; n_ without quaternions)
  const bool quaternions_;         // the model has free bodies or ball joints
  const std::vector<int> q_of_v_;  // PositionOfVelocity (coordinate_step.h)
  const BaumgarteParameters gains_;
  const double projection_tolerance_;
  Data data_;
  LoopConstraints constraints_;
  LoopSolver solver_;
  LoopRank rank_;
  std::vector<int> prescribed_;
  Eigen::VectorXd q_, qd_, qdd_, effort_, force_, minv_force_;
  Eigen::VectorXd drive_q_;  // with quaternions: positions by velocity coordinate, for the drives
  Eigen::VectorXd held_q_, held_qd_, held_qdd_;
  Eigen::VectorXd phi_, phi_dot_, bias_, b_, mu_;
  Eigen::MatrixXd G_, A_, Y_, S_;
  Eigen::LLT<Eigen::MatrixXd> mass_llt_, s_llt_;
  RowConditioning conditioning_{0, 0};  // ConstraintConditioning's workspace
  DriveSet::Workspace drive_workspace_;
  ContactForces* const contact_;  // null without contact
  Eigen::VectorXd contact_tau_;   // J^T f of the contacts (nv)
};

}  // namespace mbstream
