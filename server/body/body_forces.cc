// The applied forces and the mass matrix of BodyMechanics: gravity, gyroscopic torques,
// joint actuators (servo and torque laws), damping and rotor inertia (armature), all acting
// along each joint's rate row h_j, and the contact forces (body_contact.h).
#include <cmath>

#include "server/body/body_contact.h"
#include "server/body/body_mechanics.h"

namespace mbstream {

void BodyMechanics::EvaluateForces() {
  const int n = bm_.n;
  // M is block diagonal but for the armature terms: only the blocks written below are
  // cleared (the rest was zeroed once by the constructor and is never written).
  for (int i = 0; i < n; ++i) {
    const int c = 6 * i;
    M_.block<6, 6>(c, c).setZero();
    M_.block<3, 3>(c, c).diagonal().setConstant(bm_.mass[i]);
    M_.block<3, 3>(c + 3, c + 3) = bm_.inertia[i];
    f_.segment<3>(c) = bm_.mass[i] * bm_.gravity;
    f_.segment<3>(c + 3) = -w_[i].cross(bm_.inertia[i] * w_[i]);
  }
  for (int j = 0; j < n; ++j) {
    const BodyJoint& joint = bm_.joints[j];
    const DriveConfig::Kind kind = drives_.kind(j);
    double near = 0.0;
    if (joint.prescribed) {
      near = q_target_[j];
    } else if (kind == DriveConfig::Kind::kPdServo) {
      near = drives_.Reference(j, t_).q;
    }
    q_(j) = JointAngle(j, near);
    const RateRow h = JointRateRow(j);
    qd_(j) = JointRate(j, nu_);
    effort_(j) = joint.prescribed ? 0.0 : drives_.ActuatorEffort(j, t_, q_(j), qd_(j));
    const double torque = effort_(j) - joint.damping * qd_(j);
    if (torque != 0.0) AddJointRow(joint, h, torque, f_);
    if (joint.armature != 0.0) {
      // qdd_j = h_j . dnu/dt + dh_j/dt . nu; the rotor's reaction -A qdd_j acts along h_j:
      // A h h^T joins the mass matrix, -A (dh/dt . nu) h the forces.
      AddJointRow(joint, h, -joint.armature * JointRateRowDerivative(j), f_);
      Eigen::Matrix<double, 12, 1> hh;
      hh << h.v_child, h.w_child, h.v_parent, h.w_parent;
      const int blocks[2] = {6 * joint.child, joint.parent == kBase ? -1 : 6 * joint.parent};
      if (blocks[1] >= 0) {  // the child-parent blocks: this joint's alone (one per child)
        M_.block<6, 6>(blocks[0], blocks[1]).setZero();
        M_.block<6, 6>(blocks[1], blocks[0]).setZero();
      }
      for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) {
          if (blocks[a] < 0 || blocks[b] < 0) continue;
          M_.block<6, 6>(blocks[a], blocks[b]).noalias() +=
              joint.armature * hh.segment<6>(6 * a) * hh.segment<6>(6 * b).transpose();
        }
      }
    }
  }
  if (contact_ != nullptr) contact_finite_ = contact_->AddTo(&f_);
}

}  // namespace mbstream
