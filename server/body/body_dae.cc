#include "server/body/body_dae.h"

#include "server/body/quaternion.h"

namespace mbstream {

BodyDae::BodyDae(const BodyModel& body_model, const DriveSet& drives, ConstraintLevel level)
    : bm_(body_model), level_(level), mechanics_(body_model, drives) {
  BodyDaePattern(bm_, level_, &column_starts_, &row_indices_);
}

void BodyDae::DifferentialIds(double* id) const {
  for (int i = 0; i < bm_.dae_size(); ++i) id[i] = i < bm_.ode_size() ? 1.0 : 0.0;
}

int BodyDae::Residual(double t, const double* y, const double* yp, double* r) {
  BodyMechanics& mech = mechanics_;
  mech.Load(t, y);
  mech.EvaluateConstraints(/*acceleration_terms=*/false);
  mech.EvaluateForces();
  const int n = bm_.n, m = bm_.m;
  for (int i = 0; i < n; ++i) {
    const int p = BodyModel::position(i), e = BodyModel::quaternion(i);
    for (int k = 0; k < 3; ++k) r[p + k] = yp[p + k] - mech.v(i)(k);
    const Vector4d rate = QuaternionRate(mech.e(i), mech.w(i));
    for (int k = 0; k < 4; ++k) r[e + k] = yp[e + k] - rate(k);
  }
  const Eigen::Map<const Eigen::VectorXd> nu_dot(yp + 7 * n, 6 * n);
  const Eigen::Map<const Eigen::VectorXd> lambda(y + 13 * n, m);
  Eigen::Map<Eigen::VectorXd> r_nu(r + 7 * n, 6 * n);
  r_nu.noalias() = mech.M() * nu_dot;
  r_nu -= mech.f();
  r_nu.noalias() -= mech.G().transpose() * lambda;
  Eigen::Map<Eigen::VectorXd> r_c(r + 13 * n, m);
  if (level_ == ConstraintLevel::kPosition) {
    r_c = mech.g();
  } else {
    r_c = mech.g_t();
    r_c.noalias() += mech.G() * mech.nu();
  }
  return 0;
}

}  // namespace mbstream
