// The joint constraints of BodyMechanics: g(x, t), G (dg/dt = G nu + g_t) and gamma (the
// velocity-product and time terms of the second derivative: G dnu/dt = gamma).
#include <cmath>

#include "server/body/body_mechanics.h"

namespace mbstream {

namespace {

// What the rows of one joint see: both bodies' poses and velocities.
struct Pair {
  const Matrix3d& RP;
  const Matrix3d& RB;
  const Vector3d& wP;
  const Vector3d& wB;
  bool has_parent;
  int cb, cp;  // columns of the bodies' velocities in nu
};

// g = (R_B u) . (R_P v), u fixed in the child, v fixed in the parent: the axis-alignment
// rows of a revolute joint and the orientation-lock rows of a prismatic one.
void DotRow(const Pair& s, const Vector3d& u, const Vector3d& v, int r, bool acceleration_terms,
            Eigen::VectorXd& g, Eigen::VectorXd& g_t, Eigen::MatrixXd& G, Eigen::VectorXd& gamma) {
  const Vector3d b_vec = s.RB * u;
  const Vector3d e_vec = s.RP * v;
  g(r) = b_vec.dot(e_vec);
  g_t(r) = 0.0;
  G.block<1, 3>(r, s.cb + 3) = u.cross(s.RB.transpose() * e_vec).transpose();
  if (s.has_parent) G.block<1, 3>(r, s.cp + 3) = v.cross(s.RP.transpose() * b_vec).transpose();
  if (acceleration_terms) {
    const Vector3d b_dot = s.RB * s.wB.cross(u);
    const Vector3d e_dot = s.RP * s.wP.cross(v);
    gamma(r) = -((s.RB * s.wB.cross(s.wB.cross(u))).dot(e_vec) + 2.0 * b_dot.dot(e_dot) +
                 b_vec.dot(s.RP * s.wP.cross(s.wP.cross(v))));
  }
}

}  // namespace

// Writes the same entries of G at every call (which depends only on the model: each joint's
// rows, in its bodies' columns); the others were zeroed once by the constructor and stay
// zero, so G is not cleared here (that was 10 kB of stores per call on the IRB 1600).
// The cut joints' rows are evaluated in full into their own rows, then the kept ones copied
// after the tree's.
void BodyMechanics::EvaluateConstraints(bool acceleration_terms) {
  const Rows tree{g_, g_t_, G_, gamma_};
  for (const BodyJoint& joint : bm_.joints) EvaluateJoint(joint, tree, acceleration_terms);
  if (bm_.cuts.empty()) return;
  const Rows cut{cut_g_, cut_g_t_, cut_G_, cut_gamma_};
  for (const BodyJoint& joint : bm_.cuts) EvaluateJoint(joint, cut, acceleration_terms);
  for (size_t i = 0; i < bm_.cut_rows.size(); ++i) {
    const BodyModel::CutRow& kept = bm_.cut_rows[i];
    const int from = bm_.cuts[kept.cut].row + kept.k;
    const int to = bm_.m_tree + static_cast<int>(i);
    g_(to) = cut_g_(from);
    g_t_(to) = cut_g_t_(from);
    G_.row(to) = cut_G_.row(from);
    if (acceleration_terms) gamma_(to) = cut_gamma_(from);
  }
}

void BodyMechanics::EvaluateJoint(const BodyJoint& joint, const Rows& out,
                                  bool acceleration_terms) {
  Eigen::VectorXd& g = out.g;
  Eigen::VectorXd& g_t = out.g_t;
  Eigen::MatrixXd& G = out.G;
  Eigen::VectorXd& gamma = out.gamma;
  const int p = joint.parent, b = joint.child, r0 = joint.row;
  const Pair s{R(p), R(b), w(p), w(b), p != kBase, 6 * b, 6 * p};

  if (joint.type == JointType::kPrismatic) {
    // Relative orientation locked (3 rows): (R_B e_i) . (R_P R_PJ e_k) = 0 for the pairs
    // (y, z), (z, x), (x, y).
    for (int k = 0; k < 3; ++k) {
      DotRow(s, joint.R_BJ * Vector3d::Unit((k + 1) % 3), joint.R_PJ * Vector3d::Unit((k + 2) % 3),
             r0 + k, acceleration_terms, g, g_t, G, gamma);
    }
    // The child's origin on the axis line (2 rows) and, when prescribed, at q(t) along
    // it (1 row): d . (R_P w_k) - s_k(t) = 0, d = JointOffset, w_k = R_PJ u_k.
    const Vector3d d = JointOffset(joint);
    const Vector3d d_dot =
        v(b) + s.RB * s.wB.cross(joint.d_B) - v(p) - s.RP * s.wP.cross(joint.d_P);
    const Vector3d d_ddot =
        s.RB * s.wB.cross(s.wB.cross(joint.d_B)) - s.RP * s.wP.cross(s.wP.cross(joint.d_P));
    for (int k = 0; k < joint.rows - 3; ++k) {
      const int r = r0 + 3 + k;
      // u1, u2 are in the child frame: in J (R_BJ^T), then in the parent (R_PJ).
      const Vector3d wk =
          k == 2 ? joint.a_P
                 : Vector3d(joint.R_PJ * (joint.R_BJ.transpose() * (k == 0 ? joint.u1 : joint.u2)));
      const Vector3d n = s.RP * wk;
      const Vector3d n_dot = s.RP * s.wP.cross(wk);
      const double target = k == 2 ? q_target_[b] : 0.0;
      g(r) = d.dot(n) - target;
      g_t(r) = k == 2 ? -qd_target_[b] : 0.0;
      G.block<1, 3>(r, s.cb) = n.transpose();
      G.block<1, 3>(r, s.cb + 3) = joint.d_B.cross(s.RB.transpose() * n).transpose();
      if (s.has_parent) {
        G.block<1, 3>(r, s.cp) = -n.transpose();
        G.block<1, 3>(r, s.cp + 3) =
            (wk.cross(s.RP.transpose() * d) - joint.d_P.cross(s.RP.transpose() * n)).transpose();
      }
      if (acceleration_terms) {
        gamma(r) =
            -(d_ddot.dot(n) + 2.0 * d_dot.dot(n_dot) + d.dot(s.RP * s.wP.cross(s.wP.cross(wk)))) +
            (k == 2 ? qdd_target_[b] : 0.0);
      }
    }
    return;
  }

  // Revolute (and ball: the joint point alone). Common joint point (3 rows, base frame): x_P +
  // R_P d_P - x_B - R_B d_B = 0.
  g.segment<3>(r0) = -JointOffset(joint);
  g_t.segment<3>(r0).setZero();
  G.block<3, 3>(r0, s.cb) = -Matrix3d::Identity();
  G.block<3, 3>(r0, s.cb + 3) = s.RB * Skew(joint.d_B);
  if (s.has_parent) {
    G.block<3, 3>(r0, s.cp) = Matrix3d::Identity();
    G.block<3, 3>(r0, s.cp + 3) = -s.RP * Skew(joint.d_P);
  }
  if (acceleration_terms) {
    gamma.segment<3>(r0) =
        -(s.RP * s.wP.cross(s.wP.cross(joint.d_P))) + s.RB * s.wB.cross(s.wB.cross(joint.d_B));
  }

  if (joint.ball) return;
  // Axes aligned (2 rows): (R_B u_k) . (R_P a_P) = 0.
  DotRow(s, joint.u1, joint.a_P, r0 + 3, acceleration_terms, g, g_t, G, gamma);
  DotRow(s, joint.u2, joint.a_P, r0 + 4, acceleration_terms, g, g_t, G, gamma);

  // Prescribed angle (rheonomic, 1 row): (R_B u1) . (R_P w(t)) = 0 with
  // w(t) = R_PJ (-sin q(t) u1 + cos q(t) u2), perpendicular to where R_B u1 belongs.
  if (joint.prescribed) {
    const int r = r0 + 5;
    const double q = q_target_[b], qd = qd_target_[b], qdd = qdd_target_[b];
    const double sq = std::sin(q), cq = std::cos(q);
    const Vector3d along = joint.R_PJ * (cq * joint.u1 + sq * joint.u2);  // where u1 belongs
    const Vector3d wt = joint.R_PJ * (-sq * joint.u1 + cq * joint.u2);
    const Vector3d wt_dot = -qd * along;
    const Vector3d wt_ddot = -qdd * along - qd * qd * wt;
    const Vector3d b_vec = s.RB * joint.u1;
    const Vector3d b_dot = s.RB * s.wB.cross(joint.u1);
    const Vector3d c_vec = s.RP * wt;
    g(r) = b_vec.dot(c_vec);
    g_t(r) = b_vec.dot(s.RP * wt_dot);
    G.block<1, 3>(r, s.cb + 3) = joint.u1.cross(s.RB.transpose() * c_vec).transpose();
    if (s.has_parent) {
      G.block<1, 3>(r, s.cp + 3) = wt.cross(s.RP.transpose() * b_vec).transpose();
    }
    if (acceleration_terms) {
      const Vector3d c_dot = s.RP * (s.wP.cross(wt) + wt_dot);
      const Vector3d c_ddot_rest =
          s.RP * (s.wP.cross(s.wP.cross(wt)) + 2.0 * s.wP.cross(wt_dot) + wt_ddot);
      gamma(r) = -((s.RB * s.wB.cross(s.wB.cross(joint.u1))).dot(c_vec) + 2.0 * b_dot.dot(c_dot) +
                   b_vec.dot(c_ddot_rest));
    }
  }
}

}  // namespace mbstream
