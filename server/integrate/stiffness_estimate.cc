#include "server/integrate/stiffness_estimate.h"

#include <algorithm>
#include <cmath>
#include <limits>
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
  const JacobianSpectrum spectrum = EstimateJacobianSpectrum(system, t, y);
  return spectrum.ok ? spectrum.largest_magnitude : -1.0;
}

JacobianSpectrum EstimateJacobianSpectrum(OdeSystem& system, double t, const double* y) {
  const JacobianSpectrum failed;
  const int n = system.size();
  if (n <= 0 || n > kMaxDenseSize) return failed;
  std::vector<double> state(y, y + n), f0(static_cast<size_t>(n)), f1(static_cast<size_t>(n));
  if (!AllFinite(state) || system.Rhs(t, state.data(), f0.data()) != 0 || !AllFinite(f0)) {
    return failed;
  }
  Eigen::MatrixXd jacobian(n, n);
  if (!system.HasJacobian() || system.Jacobian(t, state.data(), f0.data(), jacobian.data()) != 0) {
    for (int j = 0; j < n; ++j) {
      const double yj = state[static_cast<size_t>(j)];
      const double h = 1e-7 * std::max(1.0, std::abs(yj));
      state[static_cast<size_t>(j)] = yj + h;
      const int code = system.Rhs(t, state.data(), f1.data());
      state[static_cast<size_t>(j)] = yj;
      if (code != 0 || !AllFinite(f1)) return failed;
      for (int i = 0; i < n; ++i) jacobian(i, j) = (f1[i] - f0[i]) / h;
    }
  }
  if (!jacobian.allFinite()) return failed;
  const Eigen::VectorXcd eigenvalues = jacobian.eigenvalues();
  JacobianSpectrum spectrum;
  spectrum.largest_magnitude = 0.0;
  spectrum.largest_real = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < eigenvalues.size(); ++i) {
    spectrum.largest_magnitude = std::max(spectrum.largest_magnitude, std::abs(eigenvalues(i)));
    spectrum.largest_real = std::max(spectrum.largest_real, eigenvalues(i).real());
  }
  spectrum.ok = std::isfinite(spectrum.largest_magnitude) && std::isfinite(spectrum.largest_real);
  return spectrum.ok ? spectrum : failed;
}

}  // namespace mbstream
