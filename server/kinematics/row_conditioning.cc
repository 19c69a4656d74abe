#include "server/kinematics/row_conditioning.h"

#include <algorithm>
#include <cmath>

namespace mbstream {

RowConditioning::RowConditioning(Eigen::Index rows, Eigen::Index cols)
    : unit_rows_(rows, cols), gram_(rows, rows), gram_eigen_(rows), lu_(rows == cols ? rows : 0) {}

double RowConditioning::Of(const Eigen::Ref<const Eigen::MatrixXd>& A) {
  const Eigen::Index k = A.rows();
  if (k == 0) return 1.0;
  for (Eigen::Index i = 0; i < k; ++i) {
    const double norm = A.row(i).norm();
    if (!(norm > 0.0)) return 0.0;
    unit_rows_.row(i) = A.row(i) / norm;
  }
  gram_.noalias() = unit_rows_ * unit_rows_.transpose();
  gram_eigen_.compute(gram_, Eigen::EigenvaluesOnly);
  if (gram_eigen_.info() != Eigen::Success) return 0.0;
  const double largest = gram_eigen_.eigenvalues()(k - 1);
  const double smallest = std::max(0.0, gram_eigen_.eigenvalues()(0));
  return largest > 0.0 ? std::sqrt(smallest / largest) : 0.0;
}

int RowConditioning::DeterminantSign(const Eigen::Ref<const Eigen::MatrixXd>& A) {
  lu_.compute(A);
  const double det = lu_.determinant();
  return det > 0.0 ? 1 : (det < 0.0 ? -1 : 0);
}

}  // namespace mbstream
