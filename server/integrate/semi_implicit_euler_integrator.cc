#include "server/integrate/semi_implicit_euler_integrator.h"

#include "shared/common/check.h"

namespace mbstream {

SemiImplicitEulerIntegrator::SemiImplicitEulerIntegrator(OdeSystem& system, double t0,
                                                         const double* y0,
                                                         const IntegratorOptions& options)
    : FixedStepIntegrator(system, t0, y0, options, /*order=*/1),
      num_positions_(system.num_positions()),
      own_rate_(system.num_velocities() != num_positions_),
      ydot_(system.size()),
      x_rate_(own_rate_ ? num_positions_ : 0) {
  MBSTREAM_CHECK(num_positions_ > 0 && num_positions_ + system.num_velocities() <= system.size());
}

int SemiImplicitEulerIntegrator::Step(double t, double h, const double* y, double* y_next) {
  const int n = state_size();
  const int np = num_positions_;
  if (const int code = rhs().Evaluate(t, y, ydot_.data()); code != 0) return code;
  for (int i = np; i < n; ++i) y_next[i] = y[i] + h * ydot_[i];  // v+, rest+
  if (own_rate_) {                                               // x+ = x + h x'(x, v+)
    rhs().system().PositionRate(y, y_next + np, x_rate_.data());
    for (int i = 0; i < np; ++i) y_next[i] = y[i] + h * x_rate_[i];
    return 0;
  }
  for (int i = 0; i < np; ++i) y_next[i] = y[i] + h * y_next[np + i];  // x+ = x + h v+
  return 0;
}

}  // namespace mbstream
