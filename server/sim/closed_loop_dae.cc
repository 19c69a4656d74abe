#include "server/sim/closed_loop_dae.h"

#include <Eigen/Cholesky>

#include "server/dynamics/crba.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/forward_kinematics.h"
#include "shared/common/check.h"

namespace mbstream {

ClosedLoopDae::ClosedLoopDae(const Model& model, const std::vector<LoopClosure>& loops,
                             const DriveSet& drives, const LoopRank& rank)
    : model_(model),
      drives_(drives),
      n_(model.num_dofs()),
      k_(rank.rank + static_cast<int>(PrescribedJoints(drives).size())),
      rank_(rank),
      prescribed_(PrescribedJoints(drives)),
      data_(model),
      constraints_(model, loops),
      q_(n_),
      v_(n_),
      vp_(n_),
      lambda_(k_),
      mu_(k_),
      tau_(n_),
      phi_(constraints_.num_rows()),
      phi_dot_(constraints_.num_rows()),
      G_(constraints_.num_rows(), n_),
      A_(k_, n_),
      conditioning_(k_, n_),
      drive_workspace_(drives.MakeWorkspace()) {
  // Every unknown may appear in every equation: a dense pattern (the mechanisms are small).
  const int size = 2 * n_ + 2 * k_;
  for (int j = 0; j < size; ++j) {
    column_starts_.push_back(static_cast<int>(row_indices_.size()));
    for (int i = 0; i < size; ++i) row_indices_.push_back(i);
  }
  column_starts_.push_back(static_cast<int>(row_indices_.size()));
}

void ClosedLoopDae::DifferentialIds(double* id) const {
  for (int i = 0; i < size(); ++i) id[i] = i < 2 * n_ ? 1.0 : 0.0;
}

void ClosedLoopDae::AbsoluteTolerances(double atol, const double* y0, double* atols) const {
  MultiplierTolerances(size(), 2 * n_, atol, y0, atols);
}

void ClosedLoopDae::Constraints(const Eigen::VectorXd& q) {
  BodyKinematics(model_, data_, q);
  constraints_.Residual(data_, q, phi_);
  constraints_.Jacobian(data_, G_);
  for (int i = 0; i < rank_.rank; ++i) A_.row(i) = G_.row(rank_.independent[i]);
  A_.bottomRows(static_cast<Eigen::Index>(prescribed_.size())).setZero();
  for (size_t h = 0; h < prescribed_.size(); ++h) {
    A_(rank_.rank + static_cast<Eigen::Index>(h), prescribed_[h]) = 1.0;
  }
}

int ClosedLoopDae::Residual(double t, const double* y, const double* yp, double* r) {
  q_ = Eigen::Map<const Eigen::VectorXd>(y, n_);
  v_ = Eigen::Map<const Eigen::VectorXd>(y + n_, n_);
  lambda_ = Eigen::Map<const Eigen::VectorXd>(y + 2 * n_, k_);
  mu_ = Eigen::Map<const Eigen::VectorXd>(y + 2 * n_ + k_, k_);
  vp_ = Eigen::Map<const Eigen::VectorXd>(yp + n_, n_);
  Constraints(q_);
  Eigen::Map<Eigen::VectorXd> r_q(r, n_), r_v(r + n_, n_), r_vel(r + 2 * n_, k_),
      r_pos(r + 2 * n_ + k_, k_);
  r_q = Eigen::Map<const Eigen::VectorXd>(yp, n_) - v_;
  r_q.noalias() -= A_.transpose() * mu_;
  drives_.ActuatorEfforts(t, q_.data(), v_.data(), drive_workspace_, tau_.data());
  for (int i = 0; i < n_; ++i) tau_(i) -= drives_.damping(i) * v_(i);
  r_v = Rnea(model_, data_, q_, v_, vp_) - tau_;
  r_v.noalias() -= A_.transpose() * lambda_;
  r_vel.noalias() = A_ * v_;
  for (int i = 0; i < rank_.rank; ++i) r_pos(i) = phi_(rank_.independent[i]);
  for (size_t h = 0; h < prescribed_.size(); ++h) {
    const int j = prescribed_[h];
    const Eigen::Index row = rank_.rank + static_cast<Eigen::Index>(h);
    const TrajectoryPoint ref = drives_.Reference(j, t);
    r_vel(row) -= ref.qd;
    r_pos(row) = q_(j) - ref.q;
  }
  return 0;
}

void ClosedLoopDae::ConsistentStart(double t0, const Eigen::VectorXd& q0,
                                    const Eigen::VectorXd& qd0, Eigen::VectorXd* y0,
                                    Eigen::VectorXd* yp0) {
  // M qdd - A^T lambda = tau - h, A qdd = -[bias; 0] + [0; qdd_ref].
  Constraints(q0);
  Eigen::VectorXd bias(constraints_.num_rows());
  constraints_.Bias(data_, qd0, bias);
  drives_.ActuatorEfforts(t0, q0.data(), qd0.data(), drive_workspace_, tau_.data());
  for (int i = 0; i < n_; ++i) tau_(i) -= drives_.damping(i) * qd0(i);
  const Eigen::VectorXd force = tau_ - NonlinearEffects(model_, data_, q0, qd0);
  const Eigen::MatrixXd M = Crba(model_, data_, q0);
  Eigen::VectorXd b(k_);
  for (int i = 0; i < rank_.rank; ++i) b(i) = -bias(rank_.independent[i]);
  for (size_t h = 0; h < prescribed_.size(); ++h) {
    b(rank_.rank + static_cast<Eigen::Index>(h)) = drives_.Reference(prescribed_[h], t0).qdd;
  }
  const Eigen::LLT<Eigen::MatrixXd> mass(M);
  const Eigen::MatrixXd Y = mass.solve(A_.transpose());
  const Eigen::VectorXd minv_force = mass.solve(force);
  const Eigen::VectorXd lambda = (A_ * Y).llt().solve(b - A_ * minv_force);
  const Eigen::VectorXd qdd = minv_force + Y * lambda;
  y0->setZero(size());
  yp0->setZero(size());
  y0->head(n_) = q0;
  y0->segment(n_, n_) = qd0;
  y0->segment(2 * n_, k_) = lambda;
  yp0->head(n_) = qd0;
  yp0->segment(n_, n_) = qdd;
}

void ClosedLoopDae::Readout(double t, const double* y, Eigen::VectorXd* effort, double* gap,
                            double* alignment, double* velocity) {
  q_ = Eigen::Map<const Eigen::VectorXd>(y, n_);
  v_ = Eigen::Map<const Eigen::VectorXd>(y + n_, n_);
  Constraints(q_);
  phi_dot_.noalias() = G_ * v_;
  *gap = constraints_.MaxGap(phi_);
  *alignment = constraints_.MaxAlignment(phi_);
  *velocity = phi_dot_.cwiseAbs().maxCoeff();
  drives_.ActuatorEfforts(t, q_.data(), v_.data(), drive_workspace_, effort->data());
  for (size_t h = 0; h < prescribed_.size(); ++h) {
    (*effort)(prescribed_[h]) = y[2 * n_ + rank_.rank + static_cast<int>(h)];
  }
}

double ClosedLoopDae::ConstraintConditioning(const double* y) {
  q_ = Eigen::Map<const Eigen::VectorXd>(y, n_);
  Constraints(q_);
  return conditioning_.Of(A_);
}

void ClosedLoopDae::Reactions(const double* y, Eigen::VectorXd* reactions) const {
  const Eigen::Map<const Eigen::VectorXd> lambda(y + 2 * n_, rank_.rank);
  constraints_.Reactions(data_, rank_.independent, lambda, *reactions);
}

double ClosedLoopDae::ConstraintPower(const double* y) const {
  double power = 0.0;
  for (int i = 0; i < rank_.rank; ++i) power += y[2 * n_ + i] * phi_dot_(rank_.independent[i]);
  return power;
}

}  // namespace mbstream
