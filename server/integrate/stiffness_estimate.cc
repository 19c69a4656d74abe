#include "server/integrate/stiffness_estimate.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

namespace mbstream {

namespace {

constexpr int kMaxDenseSize = 2000;  // states; a dense eigen-decomposition beyond is too slow

bool AllFinite(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

}  // namespace

double LargestEigenvalueEstimate(OdeSystem& system, double t, const double* y) {
  const int n = system.size();
  if (n <= 0 || n > kMaxDenseSize) return -1.0;
  std::vector<double> state(y, y + n), f0(static_cast<size_t>(n)), f1(static_cast<size_t>(n));
  if (!AllFinite(state) || system.Rhs(t, state.data(), f0.data()) != 0 || !AllFinite(f0)) {
    return -1.0;
  }
  Eigen::MatrixXd jacobian(n, n);
  if (!system.HasJacobian() || system.Jacobian(t, state.data(), f0.data(), jacobian.data()) != 0) {
    for (int j = 0; j < n; ++j) {
      const double yj = state[static_cast<size_t>(j)];
      const double h = 1e-7 * std::max(1.0, std::abs(yj));
      state[static_cast<size_t>(j)] = yj + h;
      const int code = system.Rhs(t, state.data(), f1.data());
      state[static_cast<size_t>(j)] = yj;
      if (code != 0 || !AllFinite(f1)) return -1.0;
      for (int i = 0; i < n; ++i) jacobian(i, j) = (f1[i] - f0[i]) / h;
    }
  }
  if (!jacobian.allFinite()) return -1.0;
  const Eigen::VectorXcd eigenvalues = jacobian.eigenvalues();
  double largest = 0.0;
  for (int i = 0; i < eigenvalues.size(); ++i)
    largest = std::max(largest, std::abs(eigenvalues(i)));
  return std::isfinite(largest) ? largest : -1.0;
}

}  // namespace mbstream
