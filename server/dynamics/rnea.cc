#include "server/dynamics/rnea.h"

#include "server/dynamics/axis_joint_steps.h"
#include "server/dynamics/free_tree.h"
#include "server/kinematics/joint_spatial_transform.h"
#include "server/kinematics/joint_transform.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// Body i's pose, velocity, acceleration and net force (base to tips), specialised on its
// joint's Shape (see joint_spatial_transform.h).
template <int Shape>
void ForwardPass(const Body& body, int i, double q, double qd, double qdd, const Vector6d& a_base,
                 Data& data) {
  JointTransformOfShape<Shape>(body.joint, q, &data.X_parent[i]);
  const Pose& X = data.X_parent[i];
  const Vector6d vJ = data.S[i] * qd;
  if (body.parent == kBase) {
    data.v[i] = vJ;
    data.a[i] = MotionToChildAcross<Shape>(X, a_base) + data.S[i] * qdd;
  } else {
    data.v[i] = MotionToChildAcross<Shape>(X, data.v[body.parent]) + vJ;
    data.a[i] = MotionToChildAcross<Shape>(X, data.a[body.parent]) + data.S[i] * qdd +
                CrossMotion(data.v[i], vJ);
  }
  const RigidInertia& inertia = body.inertia;
  data.f[i] = inertia.Apply(data.a[i]) + CrossForce(data.v[i], inertia.Apply(data.v[i]));
}

// The same for a revolute joint about coordinate axis K with an unrotated origin, in scalars
// (axis_joint_steps.h).
template <int K>
void ForwardPassAboutAxis(const Body& body, int i, double q, double qd, double qdd,
                          const Vector6d& a_base, Data& data) {
  using namespace axis_joint;
  const Vector3d& p = body.joint.X_PJ.p;
  const AxisRotation r = WritePose<K>(q, p, &data.X_parent[i]);
  double* v = data.v[i].data();
  double* a = data.a[i].data();
  if (body.parent == kBase) {
    for (int e = 0; e < 6; ++e) v[e] = 0.0;
    v[K] = qd;
    MotionToChild<K>(r, p.data(), a_base.data(), a);
    a[K] += qdd;
  } else {
    MotionToChild<K>(r, p.data(), data.v[body.parent].data(), v);
    v[K] += qd;
    MotionToChild<K>(r, p.data(), data.a[body.parent].data(), a);
    a[K] += qdd;
    AddCrossJointRate<K>(v, qd, a);
  }
  double h[6];
  double* f = data.f[i].data();
  ApplyInertia(body.inertia, a, f);
  ApplyInertia(body.inertia, v, h);
  CrossForce<true>(v, h, f);
}

// Rnea for a model without free bodies: the specialised passes, in a function of their own so
// that the free bodies' test does not change how they compile (callgrind: docs/performance.md).
[[gnu::noinline]] const Eigen::VectorXd& FixedBaseRnea(const Model& model, Data& data,
                                                       ConstVectorRef q, ConstVectorRef qd,
                                                       ConstVectorRef qdd) {
  const int n = model.num_bodies();
  MBSTREAM_CHECK(q.size() == n && qd.size() == n && qdd.size() == n);
  Vector6d a_base = Vector6d::Zero();
  a_base.tail<3>() = -model.gravity;  // gravity as an upward acceleration of the base
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    DispatchJointShape(body.joint, [&](auto shape) {
      if constexpr (shape() >= 0) {
        ForwardPassAboutAxis<shape()>(body, i, q(i), qd(i), qdd(i), a_base, data);
      } else {
        ForwardPass<shape()>(body, i, q(i), qd(i), qdd(i), a_base, data);
      }
    });
  }
  for (int i = n - 1; i >= 0; --i) {
    const Body& body = model.bodies[i];
    DispatchJointShape(body.joint, [&](auto shape) {
      if constexpr (shape() >= 0) {
        data.tau(i) = data.f[i](shape()) + body.joint.armature * qdd(i);
        if (body.parent != kBase) {
          axis_joint::AddForceToParent<shape()>(axis_joint::RotationOf<shape()>(data.X_parent[i]),
                                                body.joint.X_PJ.p.data(), data.f[i].data(),
                                                data.f[body.parent].data());
        }
      } else {
        data.tau(i) = data.S[i].dot(data.f[i]) + body.joint.armature * qdd(i);
        if (body.parent != kBase) {
          data.f[body.parent] += ForceToParentAcross<shape()>(data.X_parent[i], data.f[i]);
        }
      }
    });
  }
  return data.tau;
}

}  // namespace

const Eigen::VectorXd& Rnea(const Model& model, Data& data, ConstVectorRef q, ConstVectorRef qd,
                            ConstVectorRef qdd) {
  if (model.has_quaternions()) {
    MBSTREAM_CHECK(q.size() == model.nq() && qd.size() == model.nv() && qdd.size() == model.nv());
    return free_tree::Rnea(model, data, q, qd, qdd);
  }
  return FixedBaseRnea(model, data, q, qd, qdd);
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
