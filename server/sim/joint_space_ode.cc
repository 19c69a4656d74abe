#include "server/sim/joint_space_ode.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "server/dynamics/aba.h"
#include "server/dynamics/crba.h"
#include "server/dynamics/hybrid_dynamics.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/kinematics/free_joint.h"
#include "server/kinematics/quaternion.h"
#include "server/sim/contact_roots.h"

namespace mbstream {

JointSpaceOde::JointSpaceOde(const Model& model, const DriveSet& drives, bool track_work,
                             ContactForces* contact)
    : model_(model),
      drives_(drives),
      n_(model.nv()),
      nq_(model.nq()),
      quaternions_(model.has_quaternions()),
      track_work_(track_work),
      data_(model),
      q_(Eigen::VectorXd::Zero(nq_)),
      qd_(Eigen::VectorXd::Zero(n_)),
      qdd_(Eigen::VectorXd::Zero(n_)),
      effort_(Eigen::VectorXd::Zero(n_)),
      tau_(Eigen::VectorXd::Zero(n_)),
      prescribed_force_(Eigen::VectorXd::Zero(n_)),
      drive_workspace_(drives.MakeWorkspace()),
      contact_(contact),
      contact_tau_(Eigen::VectorXd::Zero(n_)) {
  for (int i = 0; i < n_; ++i) {
    (drives.prescribed(i) ? prescribed_ : free_).push_back(i);
    prescribed_mask_.push_back(drives.prescribed(i) ? 1 : 0);
  }
  // Every drive law is affine in (q, qd) (servo: kp (q_ref - q) + kd (qd_ref - qd); torque
  // laws and passive joints: constant in both), so two differences give its exact slopes.
  effort_dq_ = Eigen::VectorXd::Zero(n_);
  effort_dqd_ = Eigen::VectorXd::Zero(n_);
  for (int i : free_) {
    const double e0 = drives.ActuatorEffort(i, 0.0, 0.0, 0.0);
    effort_dq_(i) = drives.ActuatorEffort(i, 0.0, 1.0, 0.0) - e0;
    effort_dqd_(i) = drives.ActuatorEffort(i, 0.0, 0.0, 1.0) - e0 - drives.damping(i);
  }
  id0_ = Eigen::VectorXd::Zero(n_);
  dqdd_ = Eigen::MatrixXd::Zero(n_, 2 * n_);
  mass_llt_ = Eigen::LLT<Eigen::MatrixXd>(n_);
  if (quaternions_) {
    q_of_v_.assign(n_, -1);
    for (const Body& body : model.bodies) {
      if (body.nv() == 1) q_of_v_[body.v_index] = body.q_index;
    }
    drive_q_ = Eigen::VectorXd::Zero(n_);
  }
}

int JointSpaceOde::JacobianNonZeros() const { return n_ + static_cast<int>(free_.size()) * 2 * n_; }

bool JointSpaceOde::Evaluate(double t, const double* y) {
  EvaluateState(t, y);
  return EvaluateAccelerations();
}

void JointSpaceOde::EvaluateFreeState(double t, const double* y) {
  for (int i = 0; i < nq_; ++i) q_(i) = y[i];
  for (int i = 0; i < n_; ++i) qd_(i) = y[nq_ + i];
  // The dynamics, the quaternions' rates and the outputs from unit quaternions (the rate
  // 1/2 quat (x) (0, w) is orthogonal to quat: the state's norm still does not change).
  for (const int k : model_.quaternions) quaternion::Normalise(&q_(k));
  for (int i : prescribed_) {  // never a free or ball joint's coordinate (ValidateRun)
    const TrajectoryPoint ref = drives_.Reference(i, t);
    if (!drives_.velocity_source(i)) q_(q_of_v_[i]) = ref.q;
    qd_(i) = ref.qd;
    qdd_(i) = ref.qdd;
  }
  drives_.ActuatorEfforts(t, DrivePositions(q_.data()), qd_.data(), drive_workspace_,
                          effort_.data());
  for (int i : free_) tau_(i) = effort_(i) - drives_.damping(i) * qd_(i);
  if (contact_ != nullptr) AddContactForces();
}

const double* JointSpaceOde::DrivePositions(const double* y) {
  if (!quaternions_) return y;
  for (int i = 0; i < n_; ++i) drive_q_(i) = q_of_v_[i] >= 0 ? y[q_of_v_[i]] : 0.0;
  return drive_q_.data();
}

void JointSpaceOde::AddContactForces() {
  BodyKinematics(model_, data_, q_);
  contact_tau_.setZero();
  contact_finite_ = contact_->AddForces(data_, qd_, &contact_tau_);
  for (int i : free_) tau_(i) += contact_tau_(i);
}

void JointSpaceOde::EvaluateState(double t, const double* y) {
  if (quaternions_) {
    EvaluateFreeState(t, y);
    return;
  }
  double* const q = q_.data();
  double* const qd = qd_.data();
  for (int i = 0; i < n_; ++i) {
    q[i] = y[i];
    qd[i] = y[n_ + i];
  }
  for (int i : prescribed_) {
    const TrajectoryPoint ref = drives_.Reference(i, t);
    if (!drives_.velocity_source(i)) q_(i) = ref.q;
    qd_(i) = ref.qd;
    qdd_(i) = ref.qdd;
  }
  // Applied efforts of the free joints: actuator minus damping. The prescribed joints'
  // entries become 0 here; ComputePrescribedEfforts fills them when asked.
  drives_.ActuatorEfforts(t, q_.data(), qd_.data(), drive_workspace_, effort_.data());
  for (int i : free_) tau_(i) = effort_(i) - drives_.damping(i) * qd_(i);
  if (contact_ != nullptr) AddContactForces();
}

bool JointSpaceOde::EvaluateAccelerations() {
  ++dynamics_evaluations_;
  if (drives_.num_prescribed() == 0) {
    qdd_ = Aba(model_, data_, q_, qd_, tau_);
  } else {
    // Hybrid dynamics: the free joints' accelerations and the prescribed joints' forces in
    // one O(n) pass (tau_'s prescribed entries and qdd_'s free ones are not read).
    qdd_ = HybridAba(model_, data_, q_, qd_, tau_, qdd_, prescribed_mask_);
    // The drives deliver what the contacts do not (their J^T f acts on these joints too).
    for (int i : prescribed_) prescribed_force_(i) = data_.tau(i) - contact_tau_(i);
  }
  return contact_finite_ && qdd_.allFinite();
}

bool JointSpaceOde::EvaluateOutputs(double t, const double* y, bool want_efforts) {
  EvaluateState(t, y);
  if (want_efforts && drives_.num_prescribed() > 0) {
    if (!EvaluateAccelerations()) return false;
    ComputePrescribedEfforts();
  }
  return q_.allFinite() && qd_.allFinite() && effort_.allFinite();
}

void JointSpaceOde::ComputePrescribedEfforts() {
  for (int i : prescribed_) effort_(i) = prescribed_force_(i) + drives_.damping(i) * qd_(i);
}

void JointSpaceOde::PositionRate(const double* q, const double* qd, double* q_rate) {
  if (!quaternions_) {
    for (int i = 0; i < n_; ++i) q_rate[i] = qd[i];
    return;
  }
  for (const Body& body : model_.bodies) {
    if (body.free()) {
      free_joint::PositionRate(q + body.q_index, qd + body.v_index, q_rate + body.q_index);
    } else if (body.ball()) {
      quaternion::Rate(q + body.q_index, qd + body.v_index, q_rate + body.q_index);
    } else {
      q_rate[body.q_index] = qd[body.v_index];
    }
  }
}

int JointSpaceOde::Project(double /*t*/, const double* y, double* correction) {
  for (int i = 0; i < size(); ++i) correction[i] = 0.0;
  for (const int k : model_.quaternions) {
    double quat[4];
    for (int e = 0; e < 4; ++e) quat[e] = y[k + e];
    quaternion::Normalise(quat);
    for (int e = 0; e < 4; ++e) correction[k + e] = quat[e] - y[k + e];
  }
  return 0;
}

int JointSpaceOde::ProjectInPlace(double /*t*/, double* y) {
  for (const int k : model_.quaternions) quaternion::Normalise(y + k);
  return 0;
}

int JointSpaceOde::Rhs(double t, const double* y, double* ydot) {
  if (!Evaluate(t, y)) return 1;  // recoverable: the solver retries with a smaller step
  if (quaternions_) {
    PositionRate(q_.data(), qd_.data(), ydot);
    for (int i = 0; i < n_; ++i) ydot[nq_ + i] = qdd_(i);
    return 0;
  }
  for (int i = 0; i < n_; ++i) {
    ydot[i] = qd_(i);
    ydot[n_ + i] = qdd_(i);
  }
  return 0;
}

int JointSpaceOde::Roots(double t, const double* y, double* g) {
  if (contact_ == nullptr) return -1;
  for (int i = 0; i < nq_; ++i) q_(i) = y[i];
  for (int i : prescribed_) {  // never a free or ball joint's coordinate (ValidateRun)
    if (!drives_.velocity_source(i)) q_(quaternions_ ? q_of_v_[i] : i) = drives_.Reference(i, t).q;
  }
  for (const int k : model_.quaternions) quaternion::Normalise(&q_(k));
  return ContactRoots(model_, data_, *contact_, t, q_, g);
}

int JointSpaceOde::Quadrature(double t, const double* y, double* qdot) {
  if (!track_work_) return -1;
  if (drives_.num_prescribed() > 0) {  // their efforts need the dynamics
    if (!Evaluate(t, y)) return 1;
    ComputePrescribedEfforts();
  } else {
    EvaluateState(t, y);
  }
  WritePower(qdot);
  return 0;
}

int JointSpaceOde::RhsAndQuadrature(double t, const double* y, double* ydot, double* qdot) {
  if (!track_work_) return -1;
  // Rhs's evaluation is the one Quadrature would repeat: EvaluateState is a function of
  // (t, y) alone, and the dynamics' results (qdd_, prescribed_force_) of its outputs.
  if (const int code = Rhs(t, y, ydot); code != 0) return code;
  ComputePrescribedEfforts();
  WritePower(qdot);
  return 0;
}

void JointSpaceOde::WritePower(double* qdot) const {
  double power = 0.0;
  for (int i = 0; i < n_; ++i) power += (effort_(i) - drives_.damping(i) * qd_(i)) * qd_(i);
  if (contact_ != nullptr) power += contact_tau_.dot(qd_);  // the contacts' power
  qdot[0] = power;
  if (contact_ != nullptr) qdot[1] = contact_->dissipated_power();
}

int JointSpaceOde::Jacobian(double /*t*/, const double* y, const double* fy,
                            double* jac_col_major) {
  if (!HasJacobian()) return -1;
  for (int i = 0; i < n_; ++i) {
    q_(i) = y[i];
    qd_(i) = y[n_ + i];
    qdd_(i) = fy[n_ + i];
  }
  id0_ = Rnea(model_, data_, q_, qd_, qdd_);
  // Columns of -dID/dq, then -dID/dqd, plus the drive slopes on the diagonal.
  const double sqrt_eps = std::sqrt(DBL_EPSILON);
  for (int j = 0; j < 2 * n_; ++j) {
    Eigen::VectorXd& x = j < n_ ? q_ : qd_;
    const int k = j < n_ ? j : j - n_;
    const double xk = x(k);
    x(k) = xk + sqrt_eps * std::max(1.0, std::abs(xk));
    const double inc = x(k) - xk;
    const Eigen::VectorXd& id = Rnea(model_, data_, q_, qd_, qdd_);
    x(k) = xk;
    for (int i = 0; i < n_; ++i) dqdd_(i, j) = (id0_(i) - id(i)) / inc;
    dqdd_(k, j) += j < n_ ? effort_dq_(k) : effort_dqd_(k);
  }
  mass_llt_.compute(Crba(model_, data_, q_));
  if (mass_llt_.info() != Eigen::Success) return 1;
  for (int j = 0; j < 2 * n_; ++j) {  // column by column: a matrix right-hand side allocates
    auto column = dqdd_.col(j);
    mass_llt_.solveInPlace(column);
  }
  if (!dqdd_.allFinite()) return 1;
  // Column-major 2n x 2n: [0 I; dqdd/dq dqdd/dqd].
  const int size = 2 * n_;
  std::fill(jac_col_major, jac_col_major + size * size, 0.0);
  for (int j = 0; j < size; ++j) {
    double* column = jac_col_major + j * size;
    if (j >= n_) column[j - n_] = 1.0;
    for (int i = 0; i < n_; ++i) column[n_ + i] = dqdd_(i, j);
  }
  return 0;
}

}  // namespace mbstream
