#include "server/dynamics/rnea.h"

#include "server/common/check.h"
#include "server/kinematics/joint_transform.h"

namespace mbstream {

const Eigen::VectorXd& Rnea(const Model& model, Data& data, ConstVectorRef q, ConstVectorRef qd,
                            ConstVectorRef qdd) {
  const int n = model.num_dofs();
  MBSTREAM_CHECK(q.size() == n && qd.size() == n && qdd.size() == n);
  Vector6d a_base = Vector6d::Zero();
  a_base.tail<3>() = -model.gravity;  // gravity as an upward acceleration of the base
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    JointTransform(body.joint, q(i), &data.X_parent[i]);
    const Pose& X = data.X_parent[i];
    const Vector6d vJ = data.S[i] * qd(i);
    if (body.parent == kBase) {
      data.v[i] = vJ;
      data.a[i] = MotionToChild(X, a_base) + data.S[i] * qdd(i);
    } else {
      data.v[i] = MotionToChild(X, data.v[body.parent]) + vJ;
      data.a[i] =
          MotionToChild(X, data.a[body.parent]) + data.S[i] * qdd(i) + CrossMotion(data.v[i], vJ);
    }
    const RigidInertia& inertia = body.inertia;
    data.f[i] = inertia.Apply(data.a[i]) + CrossForce(data.v[i], inertia.Apply(data.v[i]));
  }
  for (int i = n - 1; i >= 0; --i) {
    const Body& body = model.bodies[i];
    data.tau(i) = data.S[i].dot(data.f[i]) + body.joint.armature * qdd(i);
    if (body.parent != kBase) {
      data.f[body.parent] += ForceToParent(data.X_parent[i], data.f[i]);
    }
  }
  return data.tau;
}

const Eigen::VectorXd& NonlinearEffects(const Model& model, Data& data, ConstVectorRef q,
                                        ConstVectorRef qd) {
  return Rnea(model, data, q, qd, data.zeros);
}

const Eigen::VectorXd& GravityVector(const Model& model, Data& data, ConstVectorRef q) {
  data.gravity_torque = Rnea(model, data, q, data.zeros, data.zeros);
  return data.gravity_torque;
}

}  // namespace mbstream
