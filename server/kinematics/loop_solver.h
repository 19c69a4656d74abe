// Solves a tree's closed-loop constraints (loop_constraints.h) for positions, velocities and
// accelerations, with some joints held at given values (prescribed joints, or none):
// minimal-norm Newton corrections on the independent rows of G and the held joints' rows.
//
// LoopSolver::Analyse picks the independent rows (the rank of G, from a column-pivoted QR of
// G^T) at a pose: redundant rows (a planar loop described with spatial joints, a
// parallelogram) are dropped, and the mechanism's mobility is n - rank. Every solve after
// that allocates nothing.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "server/kinematics/loop_constraints.h"
#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

// The rank of the loop constraints at a pose.
struct LoopRank {
  int equations = 0;             // rows of G (every cut joint's equations)
  int rank = 0;                  // independent rows
  std::vector<int> independent;  // their indices, ascending
  int mobility = 0;              // degrees of freedom of the mechanism: n - rank
};

// Independent rows of G (rows x n): |R_kk| of a column-pivoted QR of G^T above
// `tolerance` times the largest. Allocates.
LoopRank RankOf(const Eigen::MatrixXd& G, double tolerance = 1e-9);

class LoopSolver {
 public:
  // `held`: the joints whose values a solve keeps as given (each a row q_i = value), by
  // velocity coordinate (one-coordinate joints only). G has nv columns (model.h).
  // Keeps references to model and constraints.
  LoopSolver(const Model& model, LoopConstraints& constraints, std::vector<int> held);

  // Takes the independent rows of G at q (Data from BodyKinematics at q) and sizes the
  // workspaces. Returns the rank (of G alone) and whether the held joints are independent
  // of the constraints and of each other (rank of [G; E] = rank + held.size()).
  LoopRank Analyse(Data& data, const Eigen::VectorXd& q, bool* held_independent);

  // Newton from q (nq values): phi(q) = 0 on the independent rows and q_i = held_values(i) for
  // the held joints (held_values by velocity coordinate, nv values), each step the
  // minimal-norm correction in velocity space, applied to q on its manifold (StepPositions,
  // coordinate_step.h: quaternions turned and renormalised). Returns the iterations, or -1 when the
  // largest residual is not below `tolerance` (m or rad) after `max_iterations`; q is then
  // the last iterate. Data holds BodyKinematics at the returned q.
  int SolvePositions(Data& data, Eigen::VectorXd& q, const Eigen::VectorXd& held_values,
                     double tolerance, int max_iterations);
  // After SolvePositions (Data at q): qd corrected by the minimal-norm change so that
  // G qd = 0 and qd_i = held_values(i) for the held joints.
  void SolveVelocities(Data& data, Eigen::VectorXd& qd, const Eigen::VectorXd& held_values);
  // After SolvePositions and SolveVelocities: qdd with G qdd + bias = 0 and
  // qdd_i = held_values(i), the minimal-norm change of qdd.
  void SolveAccelerations(Data& data, const Eigen::VectorXd& qd, Eigen::VectorXd& qdd,
                          const Eigen::VectorXd& held_values);

  // After SolveVelocities at q: mu with A^T mu = force in the least-squares sense, A the
  // independent rows of G then the held joints' rows (exact when they determine every
  // joint): the constraint forces' multipliers, then the held joints' efforts.
  void Multipliers(const Eigen::VectorXd& force, Eigen::VectorXd& mu);

  // The last full residual and velocity residual (every row of G) of SolvePositions and
  // SolveVelocities: for the run's constraint residuals.
  const Eigen::VectorXd& residual() const { return phi_; }
  const Eigen::VectorXd& velocity_residual() const { return phi_dot_; }
  // After SolveVelocities: A = [G (independent rows); E (held joints)] at its q.
  const Eigen::MatrixXd& constraint_rows() const { return A_; }
  int num_rows() const { return static_cast<int>(rows_.size() + held_.size()); }

 private:
  // A = [G(rows_); E] from the current G_, and its factorisation A A^T.
  void BuildA();
  // x += minimal-norm correction making A x = target: x -= A^T (A A^T)^-1 (A x - target).
  void Correct(Eigen::VectorXd& x);
  // The same correction of positions q (nq): q (+) -dx on the manifold (Correct without
  // quaternions).
  void CorrectPositions(Eigen::VectorXd& q);

  const Model& model_;
  LoopConstraints& constraints_;
  const std::vector<int> held_;
  const std::vector<int> q_of_v_;  // PositionOfVelocity
  std::vector<int> rows_;          // independent rows of G
  Eigen::MatrixXd G_, A_, AAt_;
  Eigen::VectorXd phi_, phi_dot_, bias_, c_, lambda_, dx_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace mbstream
