#include "server/drives/trajectory.h"

#include <algorithm>
#include <cmath>

#include "shared/common/check.h"

namespace mbstream {

TrajectoryEvaluator::TrajectoryEvaluator(const Trajectory& trajectory) : trajectory_(trajectory) {
  if (trajectory_.kind == Trajectory::Kind::kSine) {
    MBSTREAM_CHECK(trajectory_.amplitude.size() == trajectory_.omega.size() &&
                   trajectory_.amplitude.size() == trajectory_.phase.size());
    return;
  }
  const std::vector<double>& t = trajectory_.times;
  const std::vector<double>& y = trajectory_.values;
  const size_t n = t.size();
  MBSTREAM_CHECK(n >= 2 && y.size() == n);
  for (size_t k = 1; k < n; ++k) MBSTREAM_CHECK(t[k] > t[k - 1]);
  // Natural cubic spline: solve the tridiagonal system for the knots' second derivatives
  // (Thomas algorithm), with m[0] = m[n-1] = 0.
  second_derivatives_.assign(n, 0.0);
  if (n == 2) return;
  std::vector<double> diag(n, 0.0), rhs(n, 0.0), upper(n, 0.0);
  for (size_t k = 1; k + 1 < n; ++k) {
    const double h0 = t[k] - t[k - 1], h1 = t[k + 1] - t[k];
    diag[k] = 2.0 * (h0 + h1);
    upper[k] = h1;
    rhs[k] = 6.0 * ((y[k + 1] - y[k]) / h1 - (y[k] - y[k - 1]) / h0);
    if (k > 1) {  // eliminate the sub-diagonal entry h0
      const double factor = h0 / diag[k - 1];
      diag[k] -= factor * upper[k - 1];
      rhs[k] -= factor * rhs[k - 1];
    }
  }
  for (size_t k = n - 2; k >= 1; --k) {
    second_derivatives_[k] = (rhs[k] - upper[k] * second_derivatives_[k + 1]) / diag[k];
  }
}

TrajectoryPoint TrajectoryEvaluator::At(double t) const {
  return trajectory_.kind == Trajectory::Kind::kSine ? SineAt(t) : SplineAt(t);
}

TrajectoryPoint TrajectoryEvaluator::SineAt(double t) const {
  TrajectoryPoint p{trajectory_.offset, 0.0, 0.0};
  for (size_t k = 0; k < trajectory_.amplitude.size(); ++k) {
    const double a = trajectory_.amplitude[k], w = trajectory_.omega[k];
    double s, c;
    ::sincos(w * t + trajectory_.phase[k], &s, &c);
    p.q += a * s;
    p.qd += a * w * c;
    p.qdd -= a * w * w * s;
  }
  return p;
}

TrajectoryPoint TrajectoryEvaluator::SplineAt(double t) const {
  const std::vector<double>& x = trajectory_.times;
  const std::vector<double>& y = trajectory_.values;
  if (t <= x.front()) return {y.front(), 0.0, 0.0};
  if (t >= x.back()) return {y.back(), 0.0, 0.0};
  const size_t k = static_cast<size_t>(std::upper_bound(x.begin(), x.end(), t) - x.begin()) - 1;
  const double h = x[k + 1] - x[k];
  const double a = (x[k + 1] - t) / h, b = (t - x[k]) / h;
  const double m0 = second_derivatives_[k], m1 = second_derivatives_[k + 1];
  TrajectoryPoint p;
  p.q = a * y[k] + b * y[k + 1] + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0;
  p.qd = (y[k + 1] - y[k]) / h + (-(3.0 * a * a - 1.0) * m0 + (3.0 * b * b - 1.0) * m1) * h / 6.0;
  p.qdd = a * m0 + b * m1;
  return p;
}

}  // namespace mbstream
