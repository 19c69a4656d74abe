#include "server/dynamics/free_tree.h"

#include <Eigen/Cholesky>

#include "server/dynamics/ball_aba_steps.h"
#include "server/kinematics/ball_joint.h"
#include "server/kinematics/free_joint.h"
#include "server/kinematics/joint_transform.h"
#include "shared/common/check.h"

namespace mbstream::free_tree {

namespace {

// Gravity as an upward acceleration of the base, in the world frame.
Vector6d BaseAcceleration(const Model& model) {
  Vector6d a_base = Vector6d::Zero();
  a_base.tail<3>() = -model.gravity;
  return a_base;
}

// Column k of a free joint's S(q) (free_joint.h): [0; R^T e_k] for k < 3, [e_(k-3); 0] after.
Vector6d FreeColumn(const Matrix3d& R, int k) {
  Vector6d s = Vector6d::Zero();
  if (k < 3) {
    s.tail<3>() = R.row(k).transpose();
  } else {
    s(k - 3) = 1.0;
  }
  return s;
}

// Column k of body i's motion subspace: a free joint's S(q), a ball joint's e_k, else S.
Vector6d Column(const Body& body, const Data& data, int i, int k) {
  if (body.free()) return FreeColumn(data.X_parent[i].R, k);
  if (body.ball()) return Vector6d::Unit(k);
  return data.S[i];
}

// S^T F for body i's joint into out (its nv values).
void ToCoordinates(const Body& body, const Data& data, int i, const Vector6d& F, double* out) {
  if (body.free()) {
    free_joint::ForceToCoordinates(data.X_parent[i].R, F, out);
  } else if (body.ball()) {
    for (int k = 0; k < 3; ++k) out[k] = F(k);
  } else {
    out[0] = data.S[i].dot(F);
  }
}

}  // namespace

void Velocities(const Model& model, Data& data, ConstVector q, ConstVector qd) {
  for (int i = 0; i < model.num_bodies(); ++i) {
    const Body& body = model.bodies[i];
    Pose& X = data.X_parent[i];
    if (body.free()) {
      free_joint::Transform(q.data() + body.q_index, &X);
      data.v[i] = free_joint::Motion(X.R, qd.data() + body.v_index);
      data.c[i] = free_joint::RateProduct(data.v[i]);
      continue;
    }
    Vector6d vJ;
    if (body.ball()) {
      ball_joint::Transform(body.joint, q.data() + body.q_index, &X);
      vJ = ball_joint::Motion(qd.data() + body.v_index);
    } else {
      JointTransform(body.joint, q(body.q_index), &X);
      vJ = data.S[i] * qd(body.v_index);
    }
    if (body.parent == kBase) {
      data.v[i] = vJ;
      data.c[i].setZero();
    } else {
      data.v[i] = MotionToChild(X, data.v[body.parent]) + vJ;
      data.c[i] = CrossMotion(data.v[i], vJ);
    }
  }
}

const Eigen::VectorXd& Rnea(const Model& model, Data& data, ConstVector q, ConstVector qd,
                            ConstVector qdd) {
  Velocities(model, data, q, qd);
  const Vector6d a_base = BaseAcceleration(model);
  for (int i = 0; i < model.num_bodies(); ++i) {
    const Body& body = model.bodies[i];
    const Pose& X = data.X_parent[i];
    const Vector6d& a_parent = body.parent == kBase ? a_base : data.a[body.parent];
    Vector6d& a = data.a[i];
    a = MotionToChild(X, a_parent) + data.c[i];
    if (body.free()) {
      a += free_joint::Motion(X.R, qdd.data() + body.v_index);
    } else if (body.ball()) {
      a += ball_joint::Motion(qdd.data() + body.v_index);
    } else {
      a += data.S[i] * qdd(body.v_index);
    }
    const RigidInertia& inertia = body.inertia;
    data.f[i] = inertia.Apply(a) + CrossForce(data.v[i], inertia.Apply(data.v[i]));
  }
  for (int i = model.num_bodies() - 1; i >= 0; --i) {
    const Body& body = model.bodies[i];
    const int v = body.v_index;
    if (body.free()) {  // a root
      free_joint::ForceToCoordinates(data.X_parent[i].R, data.f[i], data.tau.data() + v);
      continue;
    }
    if (body.ball()) {
      ToCoordinates(body, data, i, data.f[i], data.tau.data() + v);
    } else {
      data.tau(v) = data.S[i].dot(data.f[i]) + body.joint.armature * qdd(v);
    }
    if (body.parent != kBase) data.f[body.parent] += ForceToParent(data.X_parent[i], data.f[i]);
  }
  return data.tau;
}

const Eigen::VectorXd& HybridAba(const Model& model, Data& data, ConstVector q, ConstVector qd,
                                 ConstVector tau, ConstVector qdd,
                                 const std::vector<unsigned char>* prescribed) {
  const auto is_prescribed = [&](int v) { return prescribed != nullptr && (*prescribed)[v]; };
  Velocities(model, data, q, qd);
  for (int i = 0; i < model.num_bodies(); ++i) {
    data.IA[i] = data.I[i];
    data.pA[i] = CrossForce(data.v[i], model.bodies[i].inertia.Apply(data.v[i]));
  }
  // Pass 2, tips to roots: a free body is a root, its articulated inertia goes nowhere.
  for (int i = model.num_bodies() - 1; i >= 0; --i) {
    const Body& body = model.bodies[i];
    const int v = body.v_index;
    if (body.free()) {
      for (int k = 0; k < kFreeNv; ++k) MBSTREAM_CHECK(!is_prescribed(v + k));
      continue;
    }
    if (body.ball()) {  // never prescribed either (the run's validation refuses drives on it)
      for (int k = 0; k < kBallNv; ++k) MBSTREAM_CHECK(!is_prescribed(v + k));
      ball_aba::BackwardStep(body, i, tau.data() + v, data);
      continue;
    }
    const Matrix6d& IA = data.IA[i];
    const Vector6d& S = data.S[i];
    if (is_prescribed(v)) {  // the whole subtree's inertia reaches the parent (RBDA 9.2)
      if (body.parent == kBase) continue;
      const Vector6d pa = data.pA[i] + IA * (data.c[i] + S * qdd(v));
      AddInertiaToParent(data.X_parent[i], IA, &data.IA[body.parent]);
      data.pA[body.parent] += ForceToParent(data.X_parent[i], pa);
      continue;
    }
    data.U[i].noalias() = IA * S;
    data.D[i] = S.dot(data.U[i]) + body.joint.armature;
    data.u[i] = tau(v) - S.dot(data.pA[i]);
    MBSTREAM_CHECK_MSG(data.D[i] > 0.0, "articulated inertia of a joint is not positive");
    if (body.parent == kBase) continue;
    const Vector6d& U = data.U[i];
    const double inv_D = 1.0 / data.D[i];
    Matrix6d Ia = IA;
    Ia.noalias() -= (U * inv_D) * U.transpose();
    const Vector6d pa = data.pA[i] + Ia * data.c[i] + U * (data.u[i] * inv_D);
    AddInertiaToParent(data.X_parent[i], Ia, &data.IA[body.parent]);
    data.pA[body.parent] += ForceToParent(data.X_parent[i], pa);
  }
  // Pass 3, roots to tips.
  const Vector6d a_base = BaseAcceleration(model);
  for (int i = 0; i < model.num_bodies(); ++i) {
    const Body& body = model.bodies[i];
    const int v = body.v_index;
    const Pose& X = data.X_parent[i];
    const Vector6d& a_parent = body.parent == kBase ? a_base : data.a[body.parent];
    if (body.ball()) {
      ball_aba::AccelerationStep(a_parent, i, data.qdd.data() + v, data);
      continue;
    }
    Vector6d& a = data.a[i];
    a = MotionToChild(X, a_parent) + data.c[i];
    if (body.free()) {
      // S^T (IA a_B + pA) = tau with S invertible: a_B = IA^-1 (S^-T tau - pA).
      const Eigen::LLT<Matrix6d> llt(data.IA[i]);
      MBSTREAM_CHECK_MSG(llt.info() == Eigen::Success,
                         "articulated inertia of a free body is not positive definite");
      const Vector6d a_B =
          llt.solve(free_joint::CoordinatesToForce(X.R, tau.data() + v) - data.pA[i]);
      free_joint::MotionToCoordinates(X.R, a_B - a, data.qdd.data() + v);
      a = a_B;
    } else if (is_prescribed(v)) {
      data.qdd(v) = qdd(v);
      a += data.S[i] * qdd(v);
      data.tau(v) = data.S[i].dot(data.IA[i] * a + data.pA[i]) + body.joint.armature * qdd(v);
    } else {
      data.qdd(v) = (data.u[i] - data.U[i].dot(a)) / data.D[i];
      a += data.S[i] * data.qdd(v);
    }
  }
  return data.qdd;
}

const Eigen::MatrixXd& Crba(const Model& model, Data& data, ConstVector q) {
  const int n = model.num_bodies();
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    if (body.free()) {
      free_joint::Transform(q.data() + body.q_index, &data.X_parent[i]);
    } else if (body.ball()) {
      ball_joint::Transform(body.joint, q.data() + body.q_index, &data.X_parent[i]);
    } else {
      JointTransform(body.joint, q(body.q_index), &data.X_parent[i]);
    }
    data.IA[i] = data.I[i];
  }
  for (int i = n - 1; i >= 0; --i) {
    const int parent = model.bodies[i].parent;
    if (parent != kBase) AddInertiaToParent(data.X_parent[i], data.IA[i], &data.IA[parent]);
  }
  Eigen::MatrixXd& M = data.M;
  double rows[kFreeNv];
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    for (int k = 0; k < body.nv(); ++k) {
      const int col = body.v_index + k;
      Vector6d F = data.IA[i] * Column(body, data, i, k);
      // The body's own block (symmetric: IA is), then each ancestor's rows and their mirror.
      ToCoordinates(body, data, i, F, rows);
      for (int r = 0; r < body.nv(); ++r) M(body.v_index + r, col) = rows[r];
      M(col, col) += body.joint.armature * (body.nv() == 1);
      for (int j = i; model.bodies[j].parent != kBase;) {
        F = ForceToParent(data.X_parent[j], F);
        j = model.bodies[j].parent;
        const Body& above = model.bodies[j];
        ToCoordinates(above, data, j, F, rows);
        for (int r = 0; r < above.nv(); ++r) {
          M(above.v_index + r, col) = M(col, above.v_index + r) = rows[r];
        }
      }
    }
  }
  return M;
}

double KineticEnergy(const Model& model, Data& data, ConstVector qd) {
  double energy = 0.0;
  for (int i = 0; i < model.num_bodies(); ++i) {
    const Body& body = model.bodies[i];
    const Pose& X = data.X_parent[i];
    if (body.free()) {
      data.v[i] = free_joint::Motion(X.R, qd.data() + body.v_index);
    } else if (body.ball()) {
      data.v[i] = ball_joint::Motion(qd.data() + body.v_index);
      if (body.parent != kBase) data.v[i] += MotionToChild(X, data.v[body.parent]);
    } else {
      const double rate = qd(body.v_index);
      data.v[i] = data.S[i] * rate;
      if (body.parent != kBase) data.v[i] += MotionToChild(X, data.v[body.parent]);
      energy += 0.5 * body.joint.armature * rate * rate;
    }
    energy += 0.5 * data.v[i].dot(body.inertia.Apply(data.v[i]));
  }
  return energy;
}

}  // namespace mbstream::free_tree
