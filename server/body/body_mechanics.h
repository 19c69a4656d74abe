// The mechanics of a body-coordinate state, evaluated into preallocated storage: poses,
// constraints (position, velocity and acceleration level), applied forces, mass matrix and
// the acceleration-level solve for accelerations and multipliers. One per run; allocates
// nothing after construction.
//
// Equations (generalized velocity nu = [v_i (base frame); w_i (body frame)] per body):
//   Newton (base frame):  m_i dv_i/dt = m_i g + forces
//   Euler  (body frame):  J_i dw_i/dt + w_i x J_i w_i = torques
//   written M dnu/dt = f + G^T lambda, where G = dg/dx (in the sense dg/dt = G nu + g_t)
//   is the constraint Jacobian. Rotor inertia (armature) of joint j adds A_j h_j h_j^T to M
//   and -A_j (dh_j/dt . nu) h_j to f, h_j being the row with qd_j = h_j . nu: exactly the
//   joint formulation's armature term.
#pragma once

#include <memory>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>

#include "server/body/body_model.h"
#include "server/body/quaternion.h"
#include "server/drives/drive_set.h"

namespace mbstream {

class BodyContact;
class ContactForces;

class BodyMechanics {
 public:
  // Keeps references to its arguments, which must outlive it.
  BodyMechanics(const BodyModel& body_model, const DriveSet& drives);
  ~BodyMechanics();

  // Adds the contact forces of `forces` (not owned, outlives this; shared by the run's
  // mechanics) to f at every EvaluateForces (body_contact.h). Allocates; call before the run.
  void UseContact(ContactForces* forces);
  // The contact (null without one) and, after EvaluateForces, whether its forces were finite
  // and their power on the bodies (W).
  BodyContact* contact() const { return contact_.get(); }
  bool contact_finite() const { return contact_finite_; }
  double contact_power() const;

  // Loads the positions and velocities (the first 13n entries of y) and the drives'
  // targets at t. Must come first.
  void Load(double t, const double* y);

  // g, G and g_t; with `acceleration_terms` also gamma (G dnu/dt = gamma on the solution).
  void EvaluateConstraints(bool acceleration_terms);
  // Joint angles (each on the branch nearest its servo reference, else in (-pi, pi]) and
  // rates, the applied force f (contact included, with UseContact) and the mass matrix M
  // (armature included). Needs Load.
  void EvaluateForces();
  // After EvaluateConstraints(true) and EvaluateForces: solves M dnu/dt = f + G^T lambda
  // with G dnu/dt = gamma - alpha (G nu + g_t) - beta g (alpha = beta = 0: the exact
  // acceleration level). Returns false when the system is singular or gives non-finite
  // values.
  bool SolveAccelerations(double alpha, double beta);

  // Joint position of joint j from the body poses: a revolute joint's angle on the branch
  // nearest `near` (rad), a prismatic joint's displacement (m).
  double JointAngle(int j, double near) const;

  // The joint-rate row h_j (qd_j = h_j . nu), by blocks: the child's and the parent's linear
  // and angular velocity coefficients (the parent's are zero for the base).
  struct RateRow {
    Vector3d v_child, w_child, v_parent, w_parent;
  };
  RateRow JointRateRow(int j) const;
  // dh_j/dt . nu: qdd_j = h_j . dnu/dt + this.
  double JointRateRowDerivative(int j) const;

  const BodyModel& model() const { return bm_; }
  const Matrix3d& R(int body) const { return R_[Slot(body)]; }
  const Vector3d& x(int body) const { return x_[Slot(body)]; }
  const Vector3d& v(int body) const { return v_[Slot(body)]; }
  const Vector3d& w(int body) const { return w_[Slot(body)]; }
  const Vector4d& e(int body) const { return e_[body]; }
  const Eigen::VectorXd& nu() const { return nu_; }
  const Eigen::VectorXd& g() const { return g_; }
  const Eigen::MatrixXd& G() const { return G_; }
  const Eigen::VectorXd& g_t() const { return g_t_; }
  const Eigen::VectorXd& gamma() const { return gamma_; }
  const Eigen::VectorXd& f() const { return f_; }
  const Eigen::MatrixXd& M() const { return M_; }
  const Eigen::VectorXd& q() const { return q_; }
  const Eigen::VectorXd& qd() const { return qd_; }
  // The actuator effort of each non-prescribed joint (servo or torque law), N*m.
  const Eigen::VectorXd& actuator_effort() const { return effort_; }
  const Eigen::VectorXd& nu_dot() const { return nu_dot_; }
  const Eigen::VectorXd& lambda() const { return lambda_; }
  // Every cut joint's rows (BodyModel::cuts, their `row`), the dropped ones included: g and
  // G after EvaluateConstraints.
  const Eigen::VectorXd& cut_g() const { return cut_g_; }
  const Eigen::VectorXd& cut_g_t() const { return cut_g_t_; }
  const Eigen::MatrixXd& cut_G() const { return cut_G_; }
  // h_j . a for a vector a of size 6n (a = nu: the joint rate).
  double JointRate(int j, const Eigen::VectorXd& a) const;

 private:
  int Slot(int body) const { return body < 0 ? bm_.n : body; }
  // Where EvaluateJoint writes a joint's rows (from its `row`).
  struct Rows {
    Eigen::VectorXd& g;
    Eigen::VectorXd& g_t;
    Eigen::MatrixXd& G;
    Eigen::VectorXd& gamma;
  };
  void EvaluateJoint(const BodyJoint& joint, const Rows& out, bool acceleration_terms);
  void AddJointRow(const BodyJoint& joint, const RateRow& h, double scale,
                   Eigen::VectorXd& target) const;
  // The vector from the joint frame's origin (fixed in the parent) to the child's origin,
  // base frame: zero for a revolute joint on the solution, the displacement for a prismatic.
  Vector3d JointOffset(const BodyJoint& joint) const;

  const BodyModel& bm_;
  const DriveSet& drives_;
  std::unique_ptr<BodyContact> contact_;  // null without contact
  bool contact_finite_ = true;
  double t_ = 0.0;
  // Per body, slot n = the fixed base.
  std::vector<Matrix3d> R_;
  std::vector<Vector3d> x_, v_, w_;
  std::vector<Vector4d> e_;
  std::vector<double> q_target_, qd_target_, qdd_target_;  // prescribed joints
  Eigen::VectorXd nu_, g_, g_t_, gamma_, f_, q_, qd_, effort_;
  Eigen::MatrixXd G_, M_;
  Eigen::VectorXd cut_g_, cut_g_t_, cut_gamma_;  // every cut row (BodyModel::cut_rows_all)
  Eigen::MatrixXd cut_G_;
  bool SolveBlockDiagonal(double alpha, double beta);
  bool SolveDense(double alpha, double beta);
  void StabilisedRhs(double alpha, double beta);

  // Acceleration solve. Without armature M is block diagonal (one 6x6 block per body) and
  // the Schur complement is assembled body by body from the rows that touch it.
  std::vector<Matrix3d> inertia_inverse_;
  std::vector<std::vector<int>> rows_of_body_;  // constraint rows with entries in body b
  Eigen::MatrixXd Gb_, GbMinv_;                 // scratch: rows_of_body x 6
  Eigen::LLT<Eigen::MatrixXd> M_llt_;
  Eigen::MatrixXd Y_;  // M^-1 G^T
  Eigen::MatrixXd S_;  // G M^-1 G^T
  Eigen::LDLT<Eigen::MatrixXd> S_ldlt_;
  Eigen::VectorXd Minv_f_, rhs_, nu_dot_, lambda_;
};

}  // namespace mbstream
