// How far a constraint matrix is from singular: its rows, each scaled to unit length, their
// smallest singular value over their largest (1: orthogonal rows; 0: dependent rows, a
// singular configuration of the mechanism). For a square matrix also the sign of its
// determinant, which changes when a motion passes through a singular configuration between
// two evaluations. The closed-loop ODE and the kinematic formulation watch both.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

namespace mbstream {

class RowConditioning {
 public:
  // For matrices of rows x cols. Allocates here only.
  RowConditioning(Eigen::Index rows, Eigen::Index cols);

  // The conditioning of A's unit rows (rows x cols as constructed); 0 for a zero row.
  // Allocates nothing.
  double Of(const Eigen::Ref<const Eigen::MatrixXd>& A);
  // The sign of det(A) (+1, -1, or 0 when singular) for a square A. Allocates nothing.
  int DeterminantSign(const Eigen::Ref<const Eigen::MatrixXd>& A);

 private:
  Eigen::MatrixXd unit_rows_, gram_;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> gram_eigen_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
};

}  // namespace mbstream
