// Closed kinematic loops as constraints on a tree's joint coordinates: phi(q) = 0.
//
// Each cut joint (server/model/loop_closure.h) gives 6 less its freedoms equations, of two
// kinds, with frame A (parent side) and frame B (child side) of the joint in the world:
// - gap rows, (p_B - p_A) . n with n a unit vector fixed in A (m): the joint's origins meet,
//   in every direction (revolute, ball, fixed) or across the axis (prismatic);
// - alignment rows, e . f with e fixed in A and f fixed in B, perpendicular when the loop
//   is closed (rad, for small errors): the axes line up (revolute), the frames keep their
//   orientation (prismatic, fixed).
// - coupling rows (a URDF <mimic>, loop_closure.h): q_b - multiplier q_a - offset, in the
//   follower's unit (rad or m); their Jacobian row is constant and their bias 0.
// The Jacobian G (velocity space: phi' = G qd, nv columns; dphi/dq without free bodies and ball
// joints) comes from the tree's kinematics (joint axes and origins in the
// world); the velocity constraint is G qd = 0 and the acceleration constraint
// G qdd + bias = 0 with bias = dG/dt qd, from the bodies' velocity-product accelerations.
// Rows can be dependent (a planar loop described with spatial joints): see loop_rank.h.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "server/model/data.h"
#include "server/model/loop_closure.h"
#include "server/model/model.h"

namespace mbstream {

// One constraint equation of a cut joint.
struct LoopRow {
  enum class Kind { kGap, kAlignment, kCoupling };
  int loop = 0;            // index into the loops
  Kind kind = Kind::kGap;  // gap (m), alignment (rad) or coupling (the follower's rad or m)
  Vector3d e_J;            // gap: n; alignment: e; in J, fixed in A
  Vector3d f_J;            // alignment: f, in J, fixed in B
};

// The loops' equations and the per-run workspace to evaluate them: allocated once, every
// evaluation allocates nothing. Keeps references to model and loops.
class LoopConstraints {
 public:
  LoopConstraints(const Model& model, const std::vector<LoopClosure>& loops);

  int num_rows() const { return static_cast<int>(rows_.size()); }
  const std::vector<LoopRow>& rows() const { return rows_; }
  const std::vector<LoopClosure>& loops() const { return loops_; }

  // phi(q) (size num_rows) after BodyKinematics (or ForwardKinematics) at q (nq values).
  void Residual(const Data& data, const Eigen::Ref<const Eigen::VectorXd>& q,
                Eigen::Ref<Eigen::VectorXd> phi) const;
  // G (num_rows x nv) after BodyKinematics at q: phi' = G v for velocities v (nv values,
  // model.h; q' = G(q) v), a ball or free joint's angular columns those of w_B in its body.
  void Jacobian(const Data& data, Eigen::Ref<Eigen::MatrixXd> G);
  // bias = dG/dt qd (size num_rows) after BodyKinematics at q: G qdd + bias is phi's second
  // time derivative.
  void Bias(const Data& data, const Eigen::Ref<const Eigen::VectorXd>& qd,
            Eigen::Ref<Eigen::VectorXd> bias);

  // The cut joints' reactions from multipliers `mu` of the rows `rows` (the others' taken as
  // 0), with the equations of motion M qdd + h = tau + G(rows)^T mu, after BodyKinematics at
  // q: 6 per loop, the force (N) then the torque (N*m, about the joint's origin) that side A
  // exerts on side B through the joint, in the world frame (side B's are -force, -torque).
  // A gap row contributes mu n, an alignment row mu (f x e); a coupling row mu along the
  // follower's axis in the world (a torque for a revolute follower, a force for a prismatic
  // one: the coupling's generalized force on the follower). Allocates nothing.
  void Reactions(const Data& data, const std::vector<int>& rows,
                 const Eigen::Ref<const Eigen::VectorXd>& mu,
                 Eigen::Ref<Eigen::VectorXd> reactions) const;

  // Largest |phi| over gap rows (m) and alignment rows (rad) of `values` (a residual, or a
  // velocity residual G qd: m/s and rad/s); a coupling row counts with the gaps when its
  // follower is prismatic, with the alignments when it is revolute.
  double MaxGap(const Eigen::Ref<const Eigen::VectorXd>& values) const;
  double MaxAlignment(const Eigen::Ref<const Eigen::VectorXd>& values) const;

 private:
  struct Side {  // frame A or B of a loop in the world
    Matrix3d R;
    Vector3d p;
  };
  Side SideA(const Data& data, const LoopClosure& loop) const;
  Side SideB(const Data& data, const LoopClosure& loop) const;
  // Whether row `r` is in metres (a gap, or a prismatic follower's coupling).
  bool InMetres(const LoopRow& row) const;
  // Adds sign * (n . Jv_P + m . Jw) over the chain of `body` to row `r` of G, for point P.
  void AddChain(const Data& data, int body, const Vector3d& p, const Vector3d& n, const Vector3d& m,
                double sign, Eigen::Ref<Eigen::MatrixXd> G, int r) const;
  // World angular velocity, origin velocity and their velocity-product accelerations.
  void VelocityKinematics(const Data& data, const Eigen::Ref<const Eigen::VectorXd>& qd);

  const Model& model_;
  const std::vector<LoopClosure>& loops_;
  std::vector<LoopRow> rows_;
  std::vector<Vector3d> w_, v_, alpha_, acc_;  // per body, world frame, at qdd = 0
};

}  // namespace mbstream
