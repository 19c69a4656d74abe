#include "server/dynamics/aba.h"

#include "server/common/check.h"
#include "server/kinematics/joint_inertia_transform.h"
#include "server/kinematics/joint_transform.h"

namespace mbstream {

const Eigen::VectorXd& Aba(const Model& model, Data& data,
                           const Eigen::Ref<const Eigen::VectorXd>& q,
                           const Eigen::Ref<const Eigen::VectorXd>& qd,
                           const Eigen::Ref<const Eigen::VectorXd>& tau) {
  const int n = model.num_dofs();
  MBSTREAM_CHECK(q.size() == n && qd.size() == n && tau.size() == n);

  // Pass 1 (base to tips): velocities, velocity-product accelerations, bias forces.
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    JointTransform(body.joint, q(i), &data.X_parent[i]);
    const Pose& X = data.X_parent[i];
    const Vector6d vJ = data.S[i] * qd(i);
    if (body.parent == kBase) {
      data.v[i] = vJ;
      data.c[i].setZero();
    } else {
      data.v[i] = MotionToChild(X, data.v[body.parent]) + vJ;
      data.c[i] = CrossMotion(data.v[i], vJ);
    }
    data.IA[i] = data.I[i];
    data.pA[i] = CrossForce(data.v[i], body.inertia.Apply(data.v[i]));
  }

  // Pass 2 (tips to base): articulated inertias and bias forces.
  for (int i = n - 1; i >= 0; --i) {
    const Body& body = model.bodies[i];
    const int k = data.S_index[i];
    if (k >= 0) {  // S is a coordinate unit vector: IA S is a column
      data.U[i] = data.IA[i].col(k);
      data.D[i] = data.U[i](k) + body.joint.armature;
      data.u[i] = tau(i) - data.pA[i](k);
    } else {
      data.U[i].noalias() = data.IA[i] * data.S[i];
      data.D[i] = data.S[i].dot(data.U[i]) + body.joint.armature;
      data.u[i] = tau(i) - data.S[i].dot(data.pA[i]);
    }
    MBSTREAM_CHECK_MSG(data.D[i] > 0.0, "articulated inertia of a joint is not positive");
    if (body.parent != kBase) {
      const double inv_D = 1.0 / data.D[i];
      Matrix6d& Ia = data.IA[i];  // no longer needed as IA: becomes the projected inertia
      Ia.noalias() -= (data.U[i] * inv_D) * data.U[i].transpose();
      const Vector6d pa = data.pA[i] + Ia * data.c[i] + data.U[i] * (data.u[i] * inv_D);
      AddInertiaAcrossJoint(body.joint, data.X_parent[i], Ia, &data.IA[body.parent]);
      data.pA[body.parent] += ForceToParent(data.X_parent[i], pa);
    }
  }

  // Pass 3 (base to tips): accelerations.
  Vector6d a_base = Vector6d::Zero();
  a_base.tail<3>() = -model.gravity;
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    const Vector6d& a_parent = body.parent == kBase ? a_base : data.a[body.parent];
    data.a[i] = MotionToChild(data.X_parent[i], a_parent) + data.c[i];
    data.qdd(i) = (data.u[i] - data.U[i].dot(data.a[i])) / data.D[i];
    data.a[i] += data.S[i] * data.qdd(i);
  }
  return data.qdd;
}

}  // namespace mbstream
