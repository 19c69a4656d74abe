// The acceleration-level solve of BodyMechanics, by the Schur complement of the mass
// matrix: G M^-1 G^T lambda = gamma' - G M^-1 f, then dnu/dt = M^-1 (f + G^T lambda).
#include "server/body/body_mechanics.h"

namespace mbstream {

bool BodyMechanics::SolveAccelerations(double alpha, double beta) {
  const bool ok = bm_.any_armature ? SolveDense(alpha, beta) : SolveBlockDiagonal(alpha, beta);
  return ok && lambda_.allFinite() && nu_dot_.allFinite();
}

// rhs_ -= G M^-1 f is done by the callers; this adds gamma and the Baumgarte terms.
void BodyMechanics::StabilisedRhs(double alpha, double beta) {
  rhs_ += gamma_;
  if (alpha != 0.0 || beta != 0.0) {
    // Baumgarte: d2g/dt2 + alpha dg/dt + beta g = 0, with dg/dt = G nu + g_t.
    rhs_.noalias() -= alpha * (G_ * nu_);
    rhs_ -= alpha * g_t_ + beta * g_;
  }
}

bool BodyMechanics::SolveBlockDiagonal(double alpha, double beta) {
  // M_b^-1 = diag(1/m_b, J_b^-1): S = sum_b G_b M_b^-1 G_b^T over each body's rows.
  S_.setZero();
  rhs_.setZero();
  for (int b = 0; b < bm_.n; ++b) {
    const std::vector<int>& rows = rows_of_body_[b];
    const auto count = static_cast<Eigen::Index>(rows.size());
    const int c = 6 * b;
    Minv_f_.segment<3>(c) = f_.segment<3>(c) / bm_.mass[b];
    Minv_f_.segment<3>(c + 3) = inertia_inverse_[b] * f_.segment<3>(c + 3);
    for (Eigen::Index i = 0; i < count; ++i) {
      Gb_.row(i) = G_.block<1, 6>(rows[i], c);
      GbMinv_.block<1, 3>(i, 0) = Gb_.block<1, 3>(i, 0) / bm_.mass[b];
      GbMinv_.block<1, 3>(i, 3) = Gb_.block<1, 3>(i, 3) * inertia_inverse_[b];  // J^-1 symmetric
    }
    for (Eigen::Index i = 0; i < count; ++i) {
      rhs_(rows[i]) -= GbMinv_.row(i).dot(f_.segment<6>(c));
      for (Eigen::Index k = 0; k < count; ++k) {
        S_(rows[i], rows[k]) += GbMinv_.row(i).dot(Gb_.row(k));
      }
    }
  }
  StabilisedRhs(alpha, beta);
  S_ldlt_.compute(S_);
  if (S_ldlt_.info() != Eigen::Success) return false;
  lambda_ = S_ldlt_.solve(rhs_);
  for (int b = 0; b < bm_.n; ++b) {
    const int c = 6 * b;
    Vector6d force = f_.segment<6>(c);
    force.noalias() += G_.middleCols<6>(c).transpose() * lambda_;
    nu_dot_.segment<3>(c) = force.head<3>() / bm_.mass[b];
    nu_dot_.segment<3>(c + 3) = inertia_inverse_[b] * force.tail<3>();
  }
  return true;
}

bool BodyMechanics::SolveDense(double alpha, double beta) {
  M_llt_.compute(M_);
  if (M_llt_.info() != Eigen::Success) return false;
  Y_ = G_.transpose();
  M_llt_.solveInPlace(Y_);
  S_.noalias() = G_ * Y_;
  S_ldlt_.compute(S_);
  if (S_ldlt_.info() != Eigen::Success) return false;
  Minv_f_ = f_;
  M_llt_.solveInPlace(Minv_f_);
  rhs_.noalias() = -(G_ * Minv_f_);
  StabilisedRhs(alpha, beta);
  lambda_ = S_ldlt_.solve(rhs_);
  nu_dot_ = Minv_f_;
  nu_dot_.noalias() += Y_ * lambda_;
  return true;
}

}  // namespace mbstream
