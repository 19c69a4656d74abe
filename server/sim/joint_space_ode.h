// The joint-space formulation: minimal coordinates, y = [q; qd] (2n states), with
// M(q) qdd + h(q, qd) = tau_drive - damping * qd.
//
// With free bodies or ball joints (model.h) y = [q (nq); qd (nv)] and q' = G(q) qd: a free
// body's or ball joint's quaternion rate is 1/2 quat (x) (0, w_B). The quaternions are kept unit by
// projection (normalising them) after each step: CVODE BDF through its projection, ARKODE, RK4 and
// semi-implicit Euler after each step (ManifoldProjection::ProjectsEveryMethod); CVODE Adams does
// not project (docs/free_bodies.md gives its drift). The right-hand side and the outputs (q())
// normalise the quaternions they read, so a frame's quaternion is unit to round-off with every
// method. Drive laws see each one-coordinate joint's position at its velocity index (a free or ball
// joint's coordinates are passive). The own Jacobian is for fixed-base models only.
//
// Prescribed joints impose q_ref(t) (or, as velocity sources, impose qd_ref(t) and take q
// from the state); the dynamics then solves for the free joints' accelerations and the
// prescribed joints' drive efforts together, in O(n) by Featherstone's hybrid dynamics
// (HybridAba: ABA with the prescribed joints' accelerations given). With no prescribed joint
// it is plain ABA. With no prescribed joint the ODE supplies its own Jacobian (see Jacobian());
// otherwise it is left to the integrator's difference quotients.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "server/contact/contact_forces.h"
#include "server/drives/drive_set.h"
#include "server/integrate/manifold_projection.h"
#include "server/integrate/ode_system.h"
#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

class JointSpaceOde : public OdeSystem, public ManifoldProjection {
 public:
  // Keeps references to model and drives, which must outlive it; `contact`, when given (not
  // owned, outlives it), adds the contact forces' J^T f to the applied forces at every
  // evaluation (server/contact/contact_forces.h), and their power to the work quadrature.
  // `track_work`: one quadrature, the work W(t) of the drives and the joint damping (see
  // Quadrature).
  JointSpaceOde(const Model& model, const DriveSet& drives, bool track_work = false,
                ContactForces* contact = nullptr);

  int size() const override { return nq_ + n_; }
  int Rhs(double t, const double* y, double* ydot) override;
  int num_positions() const override { return nq_; }
  int num_velocities() const override { return n_; }
  // q' = G(q) qd: qd itself without quaternions.
  void PositionRate(const double* q, const double* qd, double* q_rate) override;

  // Every quaternion normalised, the free bodies' and the ball joints' (Model::quaternions;
  // nothing to do without them).
  bool Projects() const override { return quaternions_; }
  bool ProjectsEveryMethod() const override { return quaternions_; }
  int Project(double t, const double* y, double* correction) override;
  int ProjectInPlace(double t, double* y) override;

  // df/dy = [0 I; dqdd/dq dqdd/dqd] when no joint is prescribed. From M qdd + h(q, qd) =
  // tau(t, q, qd) at fixed qdd: dqdd/dx = M^-1 (dtau/dx - dID/dx), x = q or qd, where ID =
  // RNEA(q, qd, qdd) and qdd = fy's second half. M by CRBA (Cholesky), dtau/dx exactly (the
  // drive laws are affine in q and qd: -kp, -kd - damping), dID/dx by forward differences
  // of RNEA: 2n + 1 RNEA calls and one CRBA instead of the 2n ABA calls and 2n drive
  // evaluations of differencing f. Allocates nothing.
  bool HasJacobian() const override {
    return !quaternions_ && contact_ == nullptr && free_.size() == static_cast<size_t>(n_);
  }
  int Jacobian(double t, const double* y, const double* fy, double* jac_col_major) override;

  // W' = sum_i (effort_i - damping_i qd_i) qd_i, J/s: the power of the drives (the
  // prescribed joints' by inverse dynamics) less the joint damping's. Integrated with the
  // ODE, W makes the energy balance E(t) - E(0) - W(t) a measure of the integrator's error,
  // not of a quadrature over the output frames. Allocates nothing.
  // With contact: the signed distances of the contact's root pairs
  // (ContactForces::SignedDistances), so that CVODE and ARKODE end a step where a contact
  // begins or ends. Allocates nothing.
  int num_roots() const override { return contact_ != nullptr ? contact_->num_root_pairs() : 0; }
  int Roots(double t, const double* y, double* g) override;

  // With contact a second quadrature: the power the contacts dissipate (ContactForces::
  // dissipated_power), whose integral RunStats.contact reports.
  int num_quadratures() const override { return track_work_ ? (contact_ != nullptr ? 2 : 1) : 0; }
  int Quadrature(double t, const double* y, double* qdot) override;
  // Rhs and Quadrature at one (t, y) with one evaluation of the dynamics (the appended
  // quadratures ask for both on every right-hand side); bit for bit the two calls' results.
  int RhsAndQuadrature(double t, const double* y, double* ydot, double* qdot) override;

  // How many times the dynamics (ABA or hybrid dynamics) ran: for tests of the work saved.
  long dynamics_evaluations() const { return dynamics_evaluations_; }

  // Structural non-zeros of df/dy: the identity of q' = qd, and full rows of the free
  // joints' accelerations.
  int JacobianNonZeros() const;

  // Evaluates the mechanism at (t, y): fills q(), qd(), qdd() (prescribed joints from their
  // references) and drive_effort() (the actuators' efforts; 0 for the prescribed joints
  // until ComputePrescribedEfforts).
  // Returns false if any acceleration is not finite. Allocates nothing.
  bool Evaluate(double t, const double* y);
  // What an output frame needs, without the dynamics when it can: q(), qd() and the
  // drive efforts (the free joints' actuator laws; the prescribed joints' inverse dynamics
  // only when `want_efforts`). Returns false when any of them is not finite.
  bool EvaluateOutputs(double t, const double* y, bool want_efforts);
  // After Evaluate: the efforts the prescribed joints' drives must deliver (inverse
  // dynamics, damping included) into drive_effort(), from the forces Evaluate's hybrid
  // dynamics computed (no further dynamics). Allocates nothing.
  void ComputePrescribedEfforts();
  const Eigen::VectorXd& q() const { return q_; }
  const Eigen::VectorXd& qd() const { return qd_; }
  const Eigen::VectorXd& qdd() const { return qdd_; }
  const Eigen::VectorXd& drive_effort() const { return effort_; }
  Data& data() { return data_; }
  // The contacts of the last evaluation (null without contact).
  const ContactForces* contact() const { return contact_; }
  // The generalised contact forces of the last evaluation (zeros without contact).
  const Eigen::VectorXd& contact_force() const { return contact_tau_; }
  // The drives' scratch, with the sampled drives' held values (DriveSet::Workspace::held).
  DriveSet::Workspace& drive_workspace() { return drive_workspace_; }
  // The positions the drive laws read from the state y (rad or m, one per velocity
  // coordinate): y itself without quaternions; with them each one-coordinate joint's q at its
  // position index, 0 for a free or ball joint's coordinates (valid until the next call or
  // evaluation). Allocates nothing.
  const double* DrivePositions(const double* y);

 private:
  void EvaluateState(double t, const double* y);      // q_, qd_, reference qdd_, efforts, tau_
  void EvaluateFreeState(double t, const double* y);  // EvaluateState with free bodies
  bool EvaluateAccelerations();                       // qdd_ of the free joints, prescribed_force_
  void WritePower(double* qdot) const;                // W' from effort_ and qd_
  void AddContactForces();                            // contact_tau_ into tau_
  const Model& model_;
  const DriveSet& drives_;
  const int n_;             // velocity coordinates (nv)
  const int nq_;            // position coordinates (nq; n_ without quaternions)
  const bool quaternions_;  // the model has quaternions (free bodies or ball joints)
  const bool track_work_;
  Data data_;
  Eigen::VectorXd q_, qd_, qdd_, effort_, tau_;
  // With quaternions: each velocity coordinate's position index (-1 for a free or ball joint's)
  // and the positions by velocity coordinate that the drive laws read (0 for those).
  std::vector<int> q_of_v_;
  Eigen::VectorXd drive_q_;
  std::vector<int> free_;                       // indices of non-prescribed joints
  std::vector<int> prescribed_;                 // indices of prescribed joints
  std::vector<unsigned char> prescribed_mask_;  // per joint: 1 = prescribed (HybridAba)
  Eigen::VectorXd prescribed_force_;            // the prescribed joints' forces from HybridAba
  DriveSet::Workspace drive_workspace_;         // for DriveSet::ActuatorEfforts
  long dynamics_evaluations_ = 0;
  ContactForces* const contact_;  // null without contact
  Eigen::VectorXd contact_tau_;   // J^T f of the contacts (nv)
  bool contact_finite_ = true;
  // For Jacobian(): the drive laws' slopes d(effort)/dq and d(effort)/dqd, workspaces.
  Eigen::VectorXd effort_dq_, effort_dqd_;
  Eigen::VectorXd id0_;
  Eigen::MatrixXd dqdd_;  // n x 2n: [dqdd/dq dqdd/dqd]
  Eigen::LLT<Eigen::MatrixXd> mass_llt_;
};

}  // namespace mbstream
