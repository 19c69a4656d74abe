#include "server/kinematics/loop_solver.h"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <utility>

#include "server/kinematics/coordinate_step.h"
#include "server/kinematics/forward_kinematics.h"
#include "shared/common/check.h"

namespace mbstream {

LoopRank RankOf(const Eigen::MatrixXd& G, double tolerance) {
  LoopRank rank;
  rank.equations = static_cast<int>(G.rows());
  rank.mobility = static_cast<int>(G.cols());
  if (G.rows() == 0) return rank;
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(G.transpose());
  const Eigen::MatrixXd& R = qr.matrixR();
  const Eigen::Index diagonal = std::min(R.rows(), R.cols());
  const double largest = diagonal > 0 ? std::abs(R(0, 0)) : 0.0;
  for (Eigen::Index k = 0; k < diagonal; ++k) {
    if (largest == 0.0 || std::abs(R(k, k)) <= tolerance * largest) break;
    rank.independent.push_back(static_cast<int>(qr.colsPermutation().indices()(k)));
  }
  std::sort(rank.independent.begin(), rank.independent.end());
  rank.rank = static_cast<int>(rank.independent.size());
  rank.mobility = static_cast<int>(G.cols()) - rank.rank;
  return rank;
}

LoopSolver::LoopSolver(const Model& model, LoopConstraints& constraints, std::vector<int> held)
    : model_(model),
      constraints_(constraints),
      held_(std::move(held)),
      q_of_v_(PositionOfVelocity(model)),
      G_(constraints.num_rows(), model.nv()),
      phi_(constraints.num_rows()),
      phi_dot_(constraints.num_rows()),
      bias_(constraints.num_rows()),
      dx_(model.nv()) {
  for (const int j : held_) {
    MBSTREAM_CHECK_MSG(q_of_v_[static_cast<size_t>(j)] >= 0,
                       "a held joint has one coordinate (not a free or ball joint's)");
  }
}

LoopRank LoopSolver::Analyse(Data& data, const Eigen::VectorXd& q, bool* held_independent) {
  const int n = model_.nv();
  BodyKinematics(model_, data, q);
  constraints_.Jacobian(data, G_);
  const LoopRank rank = RankOf(G_);
  rows_ = rank.independent;
  Eigen::MatrixXd GE(G_.rows() + static_cast<Eigen::Index>(held_.size()), n);
  GE.topRows(G_.rows()) = G_;
  GE.bottomRows(static_cast<Eigen::Index>(held_.size())).setZero();
  for (size_t h = 0; h < held_.size(); ++h)
    GE(G_.rows() + static_cast<Eigen::Index>(h), held_[h]) = 1.0;
  *held_independent = RankOf(GE).rank == rank.rank + static_cast<int>(held_.size());
  const int k = num_rows();
  A_.resize(k, n);
  AAt_.resize(k, k);
  c_.resize(k);
  lambda_.resize(k);
  llt_ = Eigen::LLT<Eigen::MatrixXd>(k);
  return rank;
}

void LoopSolver::BuildA() {
  const int r = static_cast<int>(rows_.size());
  for (int i = 0; i < r; ++i) A_.row(i) = G_.row(rows_[i]);
  A_.bottomRows(static_cast<Eigen::Index>(held_.size())).setZero();
  for (size_t h = 0; h < held_.size(); ++h) A_(r + static_cast<Eigen::Index>(h), held_[h]) = 1.0;
  AAt_.noalias() = A_ * A_.transpose();
  llt_.compute(AAt_);
}

void LoopSolver::Correct(Eigen::VectorXd& x) {
  lambda_ = llt_.solve(c_);
  dx_.noalias() = A_.transpose() * lambda_;
  x -= dx_;
}

void LoopSolver::CorrectPositions(Eigen::VectorXd& q) {
  if (!model_.has_quaternions()) {
    Correct(q);
    return;
  }
  lambda_ = llt_.solve(c_);
  dx_.noalias() = A_.transpose() * lambda_;
  StepPositions(model_, dx_, -1.0, q);  // q (+) -dx: the quaternions turned on their sphere
}

int LoopSolver::SolvePositions(Data& data, Eigen::VectorXd& q, const Eigen::VectorXd& held_values,
                               double tolerance, int max_iterations) {
  MBSTREAM_CHECK(held_values.size() == model_.nv() && q.size() == model_.nq());
  const int r = static_cast<int>(rows_.size());
  for (int iteration = 0;; ++iteration) {
    BodyKinematics(model_, data, q);
    constraints_.Residual(data, q, phi_);
    double largest = phi_.size() > 0 ? phi_.cwiseAbs().maxCoeff() : 0.0;
    for (int i = 0; i < r; ++i) c_(i) = phi_(rows_[i]);
    for (size_t h = 0; h < held_.size(); ++h) {
      const double d = q(q_of_v_[static_cast<size_t>(held_[h])]) - held_values(held_[h]);
      c_(r + static_cast<Eigen::Index>(h)) = d;
      largest = std::max(largest, std::abs(d));
    }
    if (largest <= tolerance) return iteration;
    if (iteration == max_iterations || !std::isfinite(largest)) return -1;
    constraints_.Jacobian(data, G_);
    BuildA();
    CorrectPositions(q);
  }
}

void LoopSolver::SolveVelocities(Data& data, Eigen::VectorXd& qd,
                                 const Eigen::VectorXd& held_values) {
  constraints_.Jacobian(data, G_);
  BuildA();
  const int r = static_cast<int>(rows_.size());
  phi_dot_.noalias() = G_ * qd;
  for (int i = 0; i < r; ++i) c_(i) = phi_dot_(rows_[i]);
  for (size_t h = 0; h < held_.size(); ++h) {
    c_(r + static_cast<Eigen::Index>(h)) = qd(held_[h]) - held_values(held_[h]);
  }
  Correct(qd);
  phi_dot_.noalias() = G_ * qd;
}

void LoopSolver::SolveAccelerations(Data& data, const Eigen::VectorXd& qd, Eigen::VectorXd& qdd,
                                    const Eigen::VectorXd& held_values) {
  constraints_.Bias(data, qd, bias_);
  const int r = static_cast<int>(rows_.size());
  for (int i = 0; i < r; ++i) c_(i) = G_.row(rows_[i]).dot(qdd) + bias_(rows_[i]);
  for (size_t h = 0; h < held_.size(); ++h) {
    c_(r + static_cast<Eigen::Index>(h)) = qdd(held_[h]) - held_values(held_[h]);
  }
  Correct(qdd);
}

void LoopSolver::Multipliers(const Eigen::VectorXd& force, Eigen::VectorXd& mu) {
  c_.noalias() = A_ * force;
  mu = llt_.solve(c_);
}

}  // namespace mbstream
