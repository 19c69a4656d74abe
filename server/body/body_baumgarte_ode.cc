#include "server/body/body_baumgarte_ode.h"

#include <cmath>

#include "server/body/body_contact.h"
#include "server/body/quaternion.h"

namespace mbstream {

BodyBaumgarteOde::BodyBaumgarteOde(const BodyModel& body_model, const DriveSet& drives,
                                   const BaumgarteParameters& parameters, bool track_work,
                                   ContactForces* contact)
    : bm_(body_model),
      parameters_(parameters),
      mechanics_(body_model, drives),
      track_work_(track_work),
      ydot_(Eigen::VectorXd::Zero(track_work ? body_model.ode_size() : 0)) {
  mechanics_.UseContact(contact);
}

const ContactForces* BodyBaumgarteOde::contact() const {
  return mechanics_.contact() != nullptr ? &mechanics_.contact()->forces() : nullptr;
}

int BodyBaumgarteOde::num_roots() const {
  return mechanics_.contact() != nullptr ? mechanics_.contact()->forces().num_root_pairs() : 0;
}

int BodyBaumgarteOde::Roots(double t, const double* y, double* g) {
  BodyContact* contact = mechanics_.contact();
  if (contact == nullptr) return -1;
  // As ContactRoots (server/sim/contact_roots.h): nothing non-finite reaches the narrow phase.
  if (!std::isfinite(t)) return 1;
  for (int k = 0; k < 7 * bm_.n; ++k) {
    if (!std::isfinite(y[k])) return 1;
  }
  mechanics_.Load(t, y);
  contact->Distances(g);
  for (int k = 0; k < num_roots(); ++k) {
    if (!std::isfinite(g[k])) return 1;
  }
  return 0;
}

int BodyBaumgarteOde::JacobianNonZeros() const {
  const int n = bm_.n;
  return n * (3 + 4 * 7) + 6 * n * 13 * n;
}

int BodyBaumgarteOde::Rhs(double t, const double* y, double* ydot) {
  BodyMechanics& mech = mechanics_;
  mech.Load(t, y);
  mech.EvaluateConstraints(/*acceleration_terms=*/true);
  mech.EvaluateForces();
  if (!mech.contact_finite()) return 1;
  if (!mech.SolveAccelerations(parameters_.alpha, parameters_.beta)) return 1;
  const int n = bm_.n;
  for (int i = 0; i < n; ++i) {
    const int p = BodyModel::position(i), e = BodyModel::quaternion(i);
    for (int k = 0; k < 3; ++k) ydot[p + k] = mech.v(i)(k);
    const Vector4d rate = QuaternionRate(mech.e(i), mech.w(i));
    for (int k = 0; k < 4; ++k) ydot[e + k] = rate(k);
  }
  const Eigen::VectorXd& nu_dot = mech.nu_dot();
  for (int k = 0; k < 6 * n; ++k) ydot[7 * n + k] = nu_dot(k);
  return 0;
}

int BodyBaumgarteOde::Quadrature(double t, const double* y, double* qdot) {
  return RhsAndQuadrature(t, y, ydot_.data(), qdot);
}

int BodyBaumgarteOde::RhsAndQuadrature(double t, const double* y, double* ydot, double* qdot) {
  if (!track_work_) return -1;
  if (const int code = Rhs(t, y, ydot); code != 0) return code;
  qdot[0] = Power();
  if (mechanics_.contact() != nullptr) qdot[1] = mechanics_.contact()->forces().dissipated_power();
  return 0;
}

double BodyBaumgarteOde::Power() const {
  const BodyMechanics& mech = mechanics_;
  double power = 0.0;
  for (const BodyJoint& joint : bm_.joints) {
    const int j = joint.child;
    const double qd = mech.qd()(j);
    const double effort =
        joint.prescribed ? mech.lambda()(joint.row + 5) : mech.actuator_effort()(j);
    power += (effort - joint.damping * qd) * qd;
  }
  return power + mech.contact_power();
}

}  // namespace mbstream
