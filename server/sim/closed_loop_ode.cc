#include "server/sim/closed_loop_ode.h"

#include <algorithm>
#include <cmath>

#include "server/dynamics/crba.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/coordinate_step.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/kinematics/free_joint.h"
#include "server/kinematics/quaternion.h"
#include "server/sim/contact_roots.h"
#include "shared/common/check.h"

namespace mbstream {

ClosedLoopOde::ClosedLoopOde(const Model& model, const std::vector<LoopClosure>& loops,
                             const DriveSet& drives, const Eigen::VectorXd& q_assembled,
                             const BaumgarteParameters& gains, double projection_tolerance,
                             ContactForces* contact)
    : model_(model),
      drives_(drives),
      n_(model.nv()),
      nq_(model.nq()),
      quaternions_(model.has_quaternions()),
      q_of_v_(PositionOfVelocity(model)),
      gains_(gains),
      projection_tolerance_(projection_tolerance),
      data_(model),
      constraints_(model, loops),
      solver_(model, constraints_, PrescribedJoints(drives)),
      prescribed_(PrescribedJoints(drives)),
      q_(nq_),
      qd_(n_),
      qdd_(n_),
      effort_(n_),
      force_(n_),
      minv_force_(n_),
      drive_q_(Eigen::VectorXd::Zero(n_)),
      held_q_(Eigen::VectorXd::Zero(n_)),
      held_qd_(Eigen::VectorXd::Zero(n_)),
      held_qdd_(Eigen::VectorXd::Zero(n_)),
      phi_(constraints_.num_rows()),
      phi_dot_(constraints_.num_rows()),
      bias_(constraints_.num_rows()),
      G_(constraints_.num_rows(), n_),
      mass_llt_(n_),
      drive_workspace_(drives.MakeWorkspace()),
      contact_(contact),
      contact_tau_(Eigen::VectorXd::Zero(n_)) {
  bool independent = false;
  rank_ = solver_.Analyse(data_, q_assembled, &independent);
  MBSTREAM_CHECK_MSG(independent, "prescribed joints must be independent of the loops");
  const int k = rank_.rank + static_cast<int>(prescribed_.size());
  A_.resize(k, n_);
  Y_.resize(n_, k);
  S_.resize(k, k);
  b_.resize(k);
  mu_.resize(k);
  s_llt_ = Eigen::LLT<Eigen::MatrixXd>(k);
  conditioning_ = RowConditioning(k, n_);
}

void ClosedLoopOde::HeldValues(double t) {
  for (int j : prescribed_) {
    const TrajectoryPoint ref = drives_.Reference(j, t);
    held_q_(j) = ref.q;
    held_qd_(j) = ref.qd;
    held_qdd_(j) = ref.qdd;
  }
}

bool ClosedLoopOde::Evaluate(double t, const double* y) {
  q_ = Eigen::Map<const Eigen::VectorXd>(y, nq_);
  qd_ = Eigen::Map<const Eigen::VectorXd>(y + nq_, n_);
  HeldValues(t);
  // Applied forces less the velocity products and gravity.
  if (quaternions_) {
    NormaliseQuaternions(model_, q_);
    for (int i = 0; i < n_; ++i) drive_q_(i) = q_of_v_[i] >= 0 ? q_(q_of_v_[i]) : 0.0;
    drives_.ActuatorEfforts(t, drive_q_.data(), qd_.data(), drive_workspace_, effort_.data());
  } else {
    drives_.ActuatorEfforts(t, q_.data(), qd_.data(), drive_workspace_, effort_.data());
  }
  force_ = effort_ - NonlinearEffects(model_, data_, q_, qd_);
  for (int i = 0; i < n_; ++i) force_(i) -= drives_.damping(i) * qd_(i);
  mass_llt_.compute(Crba(model_, data_, q_));
  if (mass_llt_.info() != Eigen::Success) return false;
  // The constraints and their Baumgarte-stabilised acceleration targets b.
  BodyKinematics(model_, data_, q_);
  bool contact_finite = true;
  if (contact_ != nullptr) {  // J^T f joins the applied forces before the constrained solve
    contact_tau_.setZero();
    contact_finite = contact_->AddForces(data_, qd_, &contact_tau_);
    force_ += contact_tau_;
  }
  constraints_.Residual(data_, q_, phi_);
  constraints_.Jacobian(data_, G_);
  constraints_.Bias(data_, qd_, bias_);
  phi_dot_.noalias() = G_ * qd_;
  const int r = rank_.rank;
  for (int i = 0; i < r; ++i) {
    const int row = rank_.independent[i];
    A_.row(i) = G_.row(row);
    b_(i) = -bias_(row) - gains_.alpha * phi_dot_(row) - gains_.beta * phi_(row);
  }
  A_.bottomRows(static_cast<Eigen::Index>(prescribed_.size())).setZero();
  for (size_t h = 0; h < prescribed_.size(); ++h) {
    const int j = prescribed_[h];
    const Eigen::Index row = r + static_cast<Eigen::Index>(h);
    A_(row, j) = 1.0;
    b_(row) = held_qdd_(j) - gains_.alpha * (qd_(j) - held_qd_(j)) -
              gains_.beta * (q_(q_of_v_[j]) - held_q_(j));
  }
  // qdd = M^-1 (force + A^T mu) with A qdd = b: (A M^-1 A^T) mu = b - A M^-1 force.
  minv_force_ = mass_llt_.solve(force_);
  Y_ = mass_llt_.solve(A_.transpose());
  S_.noalias() = A_ * Y_;
  s_llt_.compute(S_);
  if (s_llt_.info() != Eigen::Success) return false;
  b_.noalias() -= A_ * minv_force_;
  mu_ = s_llt_.solve(b_);
  qdd_ = minv_force_;
  qdd_.noalias() += Y_ * mu_;
  for (size_t h = 0; h < prescribed_.size(); ++h) {
    effort_(prescribed_[h]) = mu_(r + static_cast<Eigen::Index>(h));
  }
  return contact_finite && qdd_.allFinite() && mu_.allFinite();
}

int ClosedLoopOde::Rhs(double t, const double* y, double* ydot) {
  if (!Evaluate(t, y)) return 1;  // singular: a smaller step may avoid the singular pose
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

int ClosedLoopOde::Quadrature(double t, const double* y, double* qdot) {
  if (contact_ == nullptr) return -1;
  if (!Evaluate(t, y)) return 1;
  qdot[0] = Power();
  qdot[1] = contact_->dissipated_power();
  return 0;
}

int ClosedLoopOde::RhsAndQuadrature(double t, const double* y, double* ydot, double* qdot) {
  if (contact_ == nullptr) return -1;
  if (const int code = Rhs(t, y, ydot); code != 0) return code;
  qdot[0] = Power();  // Rhs's evaluation, a function of (t, y) alone
  qdot[1] = contact_->dissipated_power();
  return 0;
}

double ClosedLoopOde::Power() const {
  double power = ConstraintPower() + ContactPower();
  for (int i = 0; i < n_; ++i) power += (effort_(i) - drives_.damping(i) * qd_(i)) * qd_(i);
  return power;
}

int ClosedLoopOde::Project(double t, const double* y, double* correction) {
  q_ = Eigen::Map<const Eigen::VectorXd>(y, nq_);
  qd_ = Eigen::Map<const Eigen::VectorXd>(y + nq_, n_);
  HeldValues(t);
  if (quaternions_) NormaliseQuaternions(model_, q_);
  if (solver_.SolvePositions(data_, q_, held_q_, projection_tolerance_, 8) < 0) return 1;
  solver_.SolveVelocities(data_, qd_, held_qd_);
  for (int i = 0; i < nq_; ++i) correction[i] = q_(i) - y[i];
  for (int i = 0; i < n_; ++i) correction[nq_ + i] = qd_(i) - y[nq_ + i];
  return 0;
}

int ClosedLoopOde::Roots(double t, const double* y, double* g) {
  if (contact_ == nullptr) return -1;
  q_ = Eigen::Map<const Eigen::VectorXd>(y, nq_);
  if (quaternions_) NormaliseQuaternions(model_, q_);
  return ContactRoots(model_, data_, *contact_, t, q_, g);
}

int ClosedLoopOde::ProjectInPlace(double /*t*/, double* y) {
  for (const int k : model_.quaternions) quaternion::Normalise(y + k);
  return 0;
}

void ClosedLoopOde::PositionRate(const double* q, const double* qd, double* q_rate) {
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

double ClosedLoopOde::QuaternionNormError(const double* y) const {
  double error = 0.0;
  for (const int k : model_.quaternions) {
    const double norm =
        std::sqrt(y[k] * y[k] + y[k + 1] * y[k + 1] + y[k + 2] * y[k + 2] + y[k + 3] * y[k + 3]);
    error = std::max(error, std::abs(norm - 1.0));
  }
  return error;
}

double ClosedLoopOde::ConstraintConditioning() { return conditioning_.Of(A_); }

double ClosedLoopOde::ConstraintPower() const {
  double power = 0.0;
  for (int i = 0; i < rank_.rank; ++i) power += mu_(i) * phi_dot_(rank_.independent[i]);
  return power;
}

void ClosedLoopOde::Residuals(double* gap, double* alignment, double* velocity) const {
  *gap = constraints_.MaxGap(phi_);
  *alignment = constraints_.MaxAlignment(phi_);
  *velocity = phi_dot_.size() > 0 ? phi_dot_.cwiseAbs().maxCoeff() : 0.0;
}

}  // namespace mbstream
