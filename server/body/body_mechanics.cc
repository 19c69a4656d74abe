#include "server/body/body_mechanics.h"

#include <algorithm>
#include <cmath>

#include "server/body/body_contact.h"
#include "server/body/quaternion.h"

namespace mbstream {

BodyMechanics::BodyMechanics(const BodyModel& body_model, const DriveSet& drives)
    : bm_(body_model),
      drives_(drives),
      R_(body_model.n + 1, Matrix3d::Identity()),
      x_(body_model.n + 1, Vector3d::Zero()),
      v_(body_model.n + 1, Vector3d::Zero()),
      w_(body_model.n + 1, Vector3d::Zero()),
      e_(body_model.n, Vector4d(1, 0, 0, 0)),
      q_target_(body_model.n, 0.0),
      qd_target_(body_model.n, 0.0),
      qdd_target_(body_model.n, 0.0) {
  const int n6 = 6 * bm_.n, m = bm_.m;
  nu_ = Eigen::VectorXd::Zero(n6);
  g_ = Eigen::VectorXd::Zero(m);
  g_t_ = Eigen::VectorXd::Zero(m);
  gamma_ = Eigen::VectorXd::Zero(m);
  f_ = Eigen::VectorXd::Zero(n6);
  q_ = Eigen::VectorXd::Zero(bm_.n);
  qd_ = Eigen::VectorXd::Zero(bm_.n);
  effort_ = Eigen::VectorXd::Zero(bm_.n);
  G_ = Eigen::MatrixXd::Zero(m, n6);
  cut_g_ = Eigen::VectorXd::Zero(bm_.cut_rows_all);
  cut_g_t_ = cut_g_;
  cut_gamma_ = cut_g_;
  cut_G_ = Eigen::MatrixXd::Zero(bm_.cut_rows_all, n6);
  M_ = Eigen::MatrixXd::Zero(n6, n6);
  M_llt_ = Eigen::LLT<Eigen::MatrixXd>(n6);
  rows_of_body_.resize(bm_.n);
  size_t most_rows = 0;
  for (int b = 0; b < bm_.n; ++b) {
    inertia_inverse_.push_back(bm_.inertia[b].inverse());
    auto add_joint = [&](int j) {
      for (int k = 0; k < bm_.joints[j].rows; ++k)
        rows_of_body_[b].push_back(bm_.joints[j].row + k);
    };
    add_joint(b);
    for (int c : bm_.children[b]) add_joint(c);
    for (size_t i = 0; i < bm_.cut_rows.size(); ++i) {
      const BodyJoint& cut = bm_.cuts[bm_.cut_rows[i].cut];
      if (cut.child == b || cut.parent == b) {
        rows_of_body_[b].push_back(bm_.m_tree + static_cast<int>(i));
      }
    }
    most_rows = std::max(most_rows, rows_of_body_[b].size());
  }
  Gb_ = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(most_rows), 6);
  GbMinv_ = Gb_;
  Y_ = Eigen::MatrixXd::Zero(n6, m);
  S_ = Eigen::MatrixXd::Zero(m, m);
  S_ldlt_ = Eigen::LDLT<Eigen::MatrixXd>(m);
  Minv_f_ = Eigen::VectorXd::Zero(n6);
  rhs_ = Eigen::VectorXd::Zero(m);
  nu_dot_ = Eigen::VectorXd::Zero(n6);
  lambda_ = Eigen::VectorXd::Zero(m);
}

BodyMechanics::~BodyMechanics() = default;

void BodyMechanics::UseContact(ContactForces* forces) {
  contact_ = forces != nullptr ? std::make_unique<BodyContact>(*this, *forces) : nullptr;
}

double BodyMechanics::contact_power() const {
  return contact_ != nullptr ? contact_->power() : 0.0;
}

void BodyMechanics::Load(double t, const double* y) {
  t_ = t;
  const int n = bm_.n;
  for (int i = 0; i < n; ++i) {
    x_[i] = Eigen::Map<const Vector3d>(y + BodyModel::position(i));
    e_[i] = Eigen::Map<const Vector4d>(y + BodyModel::quaternion(i));
    R_[i] = QuaternionRotation(e_[i]);
    v_[i] = Eigen::Map<const Vector3d>(y + bm_.velocity(i));
    w_[i] = Eigen::Map<const Vector3d>(y + bm_.omega(i));
    nu_.segment<3>(6 * i) = v_[i];
    nu_.segment<3>(6 * i + 3) = w_[i];
  }
  for (int j = 0; j < n; ++j) {
    if (!bm_.joints[j].prescribed) continue;
    const TrajectoryPoint ref = drives_.Reference(j, t);
    q_target_[j] = ref.q + bm_.joints[j].q_offset;
    qd_target_[j] = ref.qd;
    qdd_target_[j] = ref.qdd;
  }
}

Vector3d BodyMechanics::JointOffset(const BodyJoint& joint) const {
  return x(joint.child) + R(joint.child) * joint.d_B - x(joint.parent) -
         R(joint.parent) * joint.d_P;
}

double BodyMechanics::JointAngle(int j, double near) const {
  const BodyJoint& joint = bm_.joints[j];
  if (joint.type == JointType::kPrismatic) {
    return JointOffset(joint).dot(R(joint.parent) * joint.a_P);
  }
  const Matrix3d R_rel = joint.R_PJ.transpose() * R(joint.parent).transpose() * R(joint.child);
  const Vector3d r1 = R_rel * joint.u1;
  const double angle = std::atan2(r1.dot(joint.u2), r1.dot(joint.u1));
  // The branch nearest `near`.
  return angle + 2.0 * M_PI * std::round((near - angle) / (2.0 * M_PI));
}

BodyMechanics::RateRow BodyMechanics::JointRateRow(int j) const {
  const BodyJoint& joint = bm_.joints[j];
  const Matrix3d& RP = R(joint.parent);
  const Matrix3d& RB = R(joint.child);
  RateRow h;
  if (joint.type == JointType::kRevolute) {
    // qd = a . w_B - (R_P^T R_B a) . w_P
    h.v_child.setZero();
    h.w_child = joint.a;
    h.v_parent.setZero();
    h.w_parent = -(RP.transpose() * (RB * joint.a));
  } else {
    // q = d . n with d = JointOffset, n = R_P a_P.
    const Vector3d n = RP * joint.a_P;
    const Vector3d d = JointOffset(joint);
    h.v_child = n;
    h.w_child = joint.d_B.cross(RB.transpose() * n);
    h.v_parent = -n;
    h.w_parent = -joint.d_P.cross(RP.transpose() * n) + joint.a_P.cross(RP.transpose() * d);
  }
  return h;
}

double BodyMechanics::JointRateRowDerivative(int j) const {
  const BodyJoint& joint = bm_.joints[j];
  const Matrix3d& RP = R(joint.parent);
  const Matrix3d& RB = R(joint.child);
  const Vector3d& wP = w(joint.parent);
  const Vector3d& wB = w(joint.child);
  if (joint.type == JointType::kRevolute) {
    // -w_P . d/dt(R_P^T R_B a); its part w_P x (...) is normal to w_P.
    return -wP.dot(RP.transpose() * (RB * wB.cross(joint.a)));
  }
  const Vector3d n = RP * joint.a_P;
  const Vector3d n_dot = RP * wP.cross(joint.a_P);
  const Vector3d d = JointOffset(joint);
  const Vector3d d_dot =
      v(joint.child) + RB * wB.cross(joint.d_B) - v(joint.parent) - RP * wP.cross(joint.d_P);
  const Vector3d d_ddot = RB * wB.cross(wB.cross(joint.d_B)) - RP * wP.cross(wP.cross(joint.d_P));
  return d_ddot.dot(n) + 2.0 * d_dot.dot(n_dot) + d.dot(RP * wP.cross(wP.cross(joint.a_P)));
}

double BodyMechanics::JointRate(int j, const Eigen::VectorXd& a) const {
  const BodyJoint& joint = bm_.joints[j];
  const RateRow h = JointRateRow(j);
  const int c = 6 * joint.child;
  double rate = h.v_child.dot(a.segment<3>(c)) + h.w_child.dot(a.segment<3>(c + 3));
  if (joint.parent != kBase) {
    const int p = 6 * joint.parent;
    rate += h.v_parent.dot(a.segment<3>(p)) + h.w_parent.dot(a.segment<3>(p + 3));
  }
  return rate;
}

void BodyMechanics::AddJointRow(const BodyJoint& joint, const RateRow& h, double scale,
                                Eigen::VectorXd& target) const {
  const int c = 6 * joint.child;
  target.segment<3>(c) += scale * h.v_child;
  target.segment<3>(c + 3) += scale * h.w_child;
  if (joint.parent != kBase) {
    const int p = 6 * joint.parent;
    target.segment<3>(p) += scale * h.v_parent;
    target.segment<3>(p + 3) += scale * h.w_parent;
  }
}

}  // namespace mbstream
