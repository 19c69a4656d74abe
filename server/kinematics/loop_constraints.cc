#include "server/kinematics/loop_constraints.h"

#include <algorithm>
#include <cmath>

#include "shared/common/check.h"

namespace mbstream {

namespace {

// Two unit vectors that make (n1, n2, axis) a right-handed orthonormal basis.
void Perpendiculars(const Vector3d& axis, Vector3d* n1, Vector3d* n2) {
  *n1 = axis.unitOrthogonal();
  *n2 = axis.cross(*n1);
}

}  // namespace

LoopConstraints::LoopConstraints(const Model& model, const std::vector<LoopClosure>& loops)
    : model_(model), loops_(loops) {
  const Vector3d ex = Vector3d::UnitX(), ey = Vector3d::UnitY(), ez = Vector3d::UnitZ();
  for (size_t k = 0; k < loops.size(); ++k) {
    const LoopClosure& loop = loops[k];
    const int i = static_cast<int>(k);
    using Kind = LoopRow::Kind;
    const Vector3d zero = Vector3d::Zero();
    auto gap = [&](const Vector3d& n) { rows_.push_back({i, Kind::kGap, n, zero}); };
    auto align = [&](const Vector3d& e, const Vector3d& f) {
      rows_.push_back({i, Kind::kAlignment, e, f});
    };
    Vector3d n1, n2;
    Perpendiculars(loop.axis, &n1, &n2);
    switch (loop.type) {
      case LoopJointType::kRevolute:
        gap(ex), gap(ey), gap(ez);
        align(loop.axis, n1), align(loop.axis, n2);
        break;
      case LoopJointType::kPrismatic:
        gap(n1), gap(n2);
        align(ey, ez), align(ez, ex), align(ex, ey);
        break;
      case LoopJointType::kBall:
        gap(ex), gap(ey), gap(ez);
        break;
      case LoopJointType::kFixed:
        gap(ex), gap(ey), gap(ez);
        align(ey, ez), align(ez, ex), align(ex, ey);
        break;
      case LoopJointType::kMimic:
        MBSTREAM_CHECK_MSG(loop.body_a >= 0 && loop.body_a < model.num_bodies() &&
                               loop.body_b >= 0 && loop.body_b < model.num_bodies() &&
                               model.bodies[loop.body_a].nv() == 1 &&
                               model.bodies[loop.body_b].nv() == 1,
                           "a coupling joins two moving one-coordinate joints");
        rows_.push_back({i, Kind::kCoupling, zero, zero});
        break;
    }
  }
  const size_t n = model.bodies.size();
  w_.assign(n, Vector3d::Zero());
  v_.assign(n, Vector3d::Zero());
  alpha_.assign(n, Vector3d::Zero());
  acc_.assign(n, Vector3d::Zero());
}

LoopConstraints::Side LoopConstraints::SideA(const Data& data, const LoopClosure& loop) const {
  if (loop.body_a == kBase) return {loop.X_AJ.R, loop.X_AJ.p};
  const Pose& X_W = data.X_world[loop.body_a];
  return {X_W.R * loop.X_AJ.R, X_W.Apply(loop.X_AJ.p)};
}

LoopConstraints::Side LoopConstraints::SideB(const Data& data, const LoopClosure& loop) const {
  if (loop.body_b == kBase) return {loop.X_BJ.R, loop.X_BJ.p};
  const Pose& X_W = data.X_world[loop.body_b];
  return {X_W.R * loop.X_BJ.R, X_W.Apply(loop.X_BJ.p)};
}

void LoopConstraints::Residual(const Data& data, const Eigen::Ref<const Eigen::VectorXd>& q,
                               Eigen::Ref<Eigen::VectorXd> phi) const {
  MBSTREAM_CHECK(phi.size() == num_rows() && q.size() == model_.nq());
  for (int r = 0; r < num_rows(); ++r) {
    const LoopRow& row = rows_[r];
    const LoopClosure& loop = loops_[row.loop];
    if (row.kind == LoopRow::Kind::kCoupling) {
      const int qb = model_.bodies[loop.body_b].q_index, qa = model_.bodies[loop.body_a].q_index;
      phi(r) = q(qb) - loop.multiplier * q(qa) - loop.offset;
      continue;
    }
    const Side a = SideA(data, loop), b = SideB(data, loop);
    phi(r) = row.kind == LoopRow::Kind::kGap ? (b.p - a.p).dot(a.R * row.e_J)
                                             : (a.R * row.e_J).dot(b.R * row.f_J);
  }
}

bool LoopConstraints::InMetres(const LoopRow& row) const {
  if (row.kind != LoopRow::Kind::kCoupling) return row.kind == LoopRow::Kind::kGap;
  return model_.bodies[loops_[row.loop].body_b].joint.type == JointType::kPrismatic;
}

void LoopConstraints::Reactions(const Data& data, const std::vector<int>& rows,
                                const Eigen::Ref<const Eigen::VectorXd>& mu,
                                Eigen::Ref<Eigen::VectorXd> reactions) const {
  MBSTREAM_CHECK(reactions.size() == 6 * static_cast<Eigen::Index>(loops_.size()));
  MBSTREAM_CHECK(mu.size() >= static_cast<Eigen::Index>(rows.size()));
  reactions.setZero();
  for (size_t i = 0; i < rows.size(); ++i) {
    const LoopRow& row = rows_[rows[i]];
    const LoopClosure& loop = loops_[row.loop];
    const double lambda = mu(static_cast<Eigen::Index>(i));
    if (row.kind == LoopRow::Kind::kCoupling) {
      const Joint& follower = model_.bodies[loop.body_b].joint;
      const Vector3d u = data.X_world[loop.body_b].R * follower.axis;
      const int slot = follower.type == JointType::kPrismatic ? 0 : 3;
      reactions.segment<3>(6 * row.loop + slot) += lambda * u;
      continue;
    }
    const Side a = SideA(data, loop);
    if (row.kind == LoopRow::Kind::kGap) {
      reactions.segment<3>(6 * row.loop) += lambda * (a.R * row.e_J);
    } else {
      const Side b = SideB(data, loop);
      reactions.segment<3>(6 * row.loop + 3) += lambda * (b.R * row.f_J).cross(a.R * row.e_J);
    }
  }
}

void LoopConstraints::AddChain(const Data& data, int body, const Vector3d& p, const Vector3d& n,
                               const Vector3d& m, double sign, Eigen::Ref<Eigen::MatrixXd> G,
                               int r) const {
  for (int j = body; j != kBase; j = model_.bodies[j].parent) {
    const Body& b = model_.bodies[j];
    const Joint& joint = b.joint;
    const int c = b.v_index;
    if (joint.type == JointType::kRevolute) {
      const Vector3d u = data.X_world[j].R * joint.axis;
      G(r, c) += sign * (n.dot(u.cross(p - data.X_world[j].p)) + m.dot(u));
    } else if (joint.type == JointType::kPrismatic) {
      const Vector3d u = data.X_world[j].R * joint.axis;
      G(r, c) += sign * n.dot(u);
    } else {
      // A ball joint's or a free joint's rotation: w_B in the body frame, about the body's
      // origin (the ball joint's centre); a free joint's translation first, in the world.
      const int w = joint.type == JointType::kFree ? c + 3 : c;
      if (joint.type == JointType::kFree) {
        for (int k = 0; k < 3; ++k) G(r, c + k) += sign * n(k);
      }
      const Vector3d s = p - data.X_world[j].p;
      for (int k = 0; k < 3; ++k) {
        const Vector3d u = data.X_world[j].R.col(k);
        G(r, w + k) += sign * (n.dot(u.cross(s)) + m.dot(u));
      }
    }
  }
}

void LoopConstraints::Jacobian(const Data& data, Eigen::Ref<Eigen::MatrixXd> G) {
  MBSTREAM_CHECK(G.rows() == num_rows() && G.cols() == model_.nv());
  G.setZero();
  const Vector3d zero = Vector3d::Zero();
  for (int r = 0; r < num_rows(); ++r) {
    const LoopRow& row = rows_[r];
    const LoopClosure& loop = loops_[row.loop];
    if (row.kind == LoopRow::Kind::kCoupling) {
      G(r, model_.bodies[loop.body_b].v_index) += 1.0;
      G(r, model_.bodies[loop.body_a].v_index) -= loop.multiplier;
      continue;
    }
    const Side a = SideA(data, loop), b = SideB(data, loop);
    if (row.kind == LoopRow::Kind::kGap) {
      // d/dt [(p_B - p_A) . n] = n . (v_B - v_A) + (n x d) . w_a.
      const Vector3d n = a.R * row.e_J;
      const Vector3d d = b.p - a.p;
      AddChain(data, loop.body_b, b.p, n, zero, 1.0, G, r);
      AddChain(data, loop.body_a, a.p, n, -n.cross(d), -1.0, G, r);
    } else {
      // d/dt [e . f] = (e x f) . (w_a - w_b).
      const Vector3d exf = (a.R * row.e_J).cross(b.R * row.f_J);
      AddChain(data, loop.body_a, zero, zero, exf, 1.0, G, r);
      AddChain(data, loop.body_b, zero, zero, exf, -1.0, G, r);
    }
  }
}

void LoopConstraints::VelocityKinematics(const Data& data,
                                         const Eigen::Ref<const Eigen::VectorXd>& qd) {
  const Vector3d zero = Vector3d::Zero();
  for (int i = 0; i < model_.num_bodies(); ++i) {
    const Body& body = model_.bodies[i];
    if (body.free()) {  // a root: w = R w_B, v = v_WB; at qdd = 0 both are constant
      const int c = body.v_index;
      w_[i] = data.X_world[i].R * Vector3d(qd(c + 3), qd(c + 4), qd(c + 5));
      v_[i] = Vector3d(qd(c), qd(c + 1), qd(c + 2));
      alpha_[i] = acc_[i] = zero;
      continue;
    }
    const int p = body.parent;
    const Vector3d& wp = p == kBase ? zero : w_[p];
    const Vector3d& vp = p == kBase ? zero : v_[p];
    const Vector3d& alp = p == kBase ? zero : alpha_[p];
    const Vector3d& ap = p == kBase ? zero : acc_[p];
    const Vector3d& op = p == kBase ? zero : data.X_world[p].p;
    const Vector3d r = data.X_world[i].p - op;
    // The joint's own angular (or, prismatic, linear) velocity in the world; a ball joint's
    // w_B is in the child frame, its centre the child's origin.
    const Vector3d uq = body.ball()
                            ? Vector3d(data.X_world[i].R * qd.segment<3>(body.v_index))
                            : Vector3d(data.X_world[i].R * body.joint.axis * qd(body.v_index));
    acc_[i] = ap + alp.cross(r) + wp.cross(wp.cross(r));
    v_[i] = vp + wp.cross(r);
    if (body.joint.type != JointType::kPrismatic) {
      w_[i] = wp + uq;
      alpha_[i] = alp + wp.cross(uq);
    } else {
      w_[i] = wp;
      alpha_[i] = alp;
      v_[i] += uq;
      acc_[i] += 2.0 * wp.cross(uq);
    }
  }
}

void LoopConstraints::Bias(const Data& data, const Eigen::Ref<const Eigen::VectorXd>& qd,
                           Eigen::Ref<Eigen::VectorXd> bias) {
  MBSTREAM_CHECK(bias.size() == num_rows() && qd.size() == model_.nv());
  VelocityKinematics(data, qd);
  const Vector3d zero = Vector3d::Zero();
  // Angular velocity and velocity-product acceleration of body k, and of a point P in it.
  auto w = [&](int k) -> const Vector3d& { return k == kBase ? zero : w_[k]; };
  auto alpha = [&](int k) -> const Vector3d& { return k == kBase ? zero : alpha_[k]; };
  auto point_v = [&](int k, const Vector3d& p) -> Vector3d {
    return k == kBase ? zero : Vector3d(v_[k] + w_[k].cross(p - data.X_world[k].p));
  };
  auto point_a = [&](int k, const Vector3d& p) -> Vector3d {
    if (k == kBase) return zero;
    const Vector3d s = p - data.X_world[k].p;
    return acc_[k] + alpha_[k].cross(s) + w_[k].cross(w_[k].cross(s));
  };
  // Second derivative (at qdd = 0) of a unit vector u fixed in body k.
  auto vector_a = [&](int k, const Vector3d& u) -> Vector3d {
    return alpha(k).cross(u) + w(k).cross(w(k).cross(u));
  };
  for (int r = 0; r < num_rows(); ++r) {
    const LoopRow& row = rows_[r];
    const LoopClosure& loop = loops_[row.loop];
    if (row.kind == LoopRow::Kind::kCoupling) {  // linear in q: no velocity product
      bias(r) = 0.0;
      continue;
    }
    const Side a = SideA(data, loop), b = SideB(data, loop);
    const int ka = loop.body_a, kb = loop.body_b;
    const Vector3d e = a.R * row.e_J;
    if (row.kind == LoopRow::Kind::kGap) {
      const Vector3d d = b.p - a.p;
      const Vector3d d_dot = point_v(kb, b.p) - point_v(ka, a.p);
      bias(r) = (point_a(kb, b.p) - point_a(ka, a.p)).dot(e) + 2.0 * d_dot.dot(w(ka).cross(e)) +
                d.dot(vector_a(ka, e));
    } else {
      const Vector3d f = b.R * row.f_J;
      bias(r) = vector_a(ka, e).dot(f) + 2.0 * w(ka).cross(e).dot(w(kb).cross(f)) +
                e.dot(vector_a(kb, f));
    }
  }
}

double LoopConstraints::MaxGap(const Eigen::Ref<const Eigen::VectorXd>& values) const {
  double m = 0.0;
  for (int r = 0; r < num_rows(); ++r) {
    if (InMetres(rows_[r])) m = std::max(m, std::abs(values(r)));
  }
  return m;
}

double LoopConstraints::MaxAlignment(const Eigen::Ref<const Eigen::VectorXd>& values) const {
  double m = 0.0;
  for (int r = 0; r < num_rows(); ++r) {
    if (!InMetres(rows_[r])) m = std::max(m, std::abs(values(r)));
  }
  return m;
}

}  // namespace mbstream
