#include "server/body/body_readout.h"

#include <algorithm>
#include <cmath>

#include "server/body/body_cuts.h"
#include "shared/common/check.h"

namespace mbstream {

BodyReadout::BodyReadout(const BodyModel& body_model, const DriveSet& drives)
    : bm_(body_model),
      mechanics_(body_model, drives),
      q_(Eigen::VectorXd::Zero(body_model.n)),
      qd_(Eigen::VectorXd::Zero(body_model.n)),
      effort_(Eigen::VectorXd::Zero(body_model.n)) {}

bool BodyReadout::Read(double t, const double* y, bool efforts) {
  BodyMechanics& mech = mechanics_;
  mech.Load(t, y);
  mech.EvaluateConstraints(/*acceleration_terms=*/efforts);
  mech.EvaluateForces();
  for (int j = 0; j < bm_.n; ++j) {
    q_(j) = mech.JointAngle(j, q_(j));
    qd_(j) = mech.qd()(j);
    effort_(j) = mech.actuator_effort()(j);
  }
  if (efforts) {
    if (!mech.SolveAccelerations(0.0, 0.0)) return false;
    for (const BodyJoint& joint : bm_.joints) {
      if (joint.prescribed) effort_(joint.child) = mech.lambda()(joint.row + 5);
    }
  }
  tcp_ = bm_.tcp_body == kBase
             ? bm_.tcp_fixed
             : Vector3d(mech.x(bm_.tcp_body) + mech.R(bm_.tcp_body) * bm_.tcp_from_com);
  kinetic_ = potential_ = 0.0;
  for (int i = 0; i < bm_.n; ++i) {
    kinetic_ += 0.5 * bm_.mass[i] * mech.v(i).squaredNorm() +
                0.5 * mech.w(i).dot(bm_.inertia[i] * mech.w(i));
    potential_ -= bm_.mass[i] * bm_.gravity.dot(mech.x(i));
    drift_.quaternion_norm = std::max(drift_.quaternion_norm, std::abs(mech.e(i).norm() - 1.0));
  }
  const Eigen::VectorXd& g = mech.g();
  for (const BodyJoint& joint : bm_.joints) {
    for (int k = 0; k < joint.rows; ++k) {
      const int r = joint.row + k;
      double& target = k < 3 ? drift_.position : drift_.orientation;
      target = std::max(target, std::abs(g(r)));
      const double velocity = mech.G().row(r).dot(mech.nu()) + mech.g_t()(r);
      drift_.velocity = std::max(drift_.velocity, std::abs(velocity));
    }
  }
  // The cut joints' rows, the dropped (dependent) ones included.
  for (const BodyJoint& cut : bm_.cuts) {
    for (int k = 0; k < cut.rows; ++k) {
      const int r = cut.row + k;
      double& target = IsPointRow(cut, k) ? drift_.position : drift_.orientation;
      target = std::max(target, std::abs(mech.cut_g()(r)));
      const double velocity = mech.cut_G().row(r).dot(mech.nu()) + mech.cut_g_t()(r);
      drift_.velocity = std::max(drift_.velocity, std::abs(velocity));
    }
  }
  return q_.allFinite() && qd_.allFinite() && effort_.allFinite() && tcp_.allFinite() &&
         std::isfinite(kinetic_) && std::isfinite(potential_);
}

void BodyReadout::CutReactions(Eigen::Ref<Eigen::VectorXd> reactions) const {
  MBSTREAM_CHECK(reactions.size() == 6 * static_cast<Eigen::Index>(bm_.cuts.size()));
  const BodyMechanics& mech = mechanics_;
  reactions.setZero();
  // The kept rows' generalized force on the cut's child body: [force, base frame; torque
  // about its centre of mass, body frame] (M dnu/dt = f + G^T lambda).
  for (size_t i = 0; i < bm_.cut_rows.size(); ++i) {
    const int r = bm_.m_tree + static_cast<int>(i);
    const int c = bm_.cut_rows[i].cut;
    const int b = bm_.cuts[c].child;
    reactions.segment<6>(6 * c) += mech.G().block<1, 6>(r, 6 * b).transpose() * mech.lambda()(r);
  }
  for (size_t c = 0; c < bm_.cuts.size(); ++c) {
    const BodyJoint& cut = bm_.cuts[c];
    const Matrix3d& R = mech.R(cut.child);
    const Vector3d force = reactions.segment<3>(6 * c);
    const Vector3d torque_com = R * reactions.segment<3>(6 * c + 3);
    // About the joint point p = x + R d_B: tau_p = tau_com + (x - p) x F.
    Vector3d torque = torque_com - (R * cut.d_B).cross(force);
    const double sign = cut.sides_swapped ? -1.0 : 1.0;  // the base side is the file's child
    reactions.segment<3>(6 * c) = sign * force;
    reactions.segment<3>(6 * c + 3) = sign * torque;
  }
}

}  // namespace mbstream
