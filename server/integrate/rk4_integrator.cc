#include "server/integrate/rk4_integrator.h"

namespace mbstream {

Rk4Integrator::Rk4Integrator(OdeSystem& system, double t0, const double* y0,
                             const IntegratorOptions& options)
    : FixedStepIntegrator(system, t0, y0, options, /*order=*/4),
      k1_(system.size()),
      k2_(system.size()),
      k3_(system.size()),
      k4_(system.size()),
      stage_(system.size()) {}

int Rk4Integrator::Step(double t, double h, const double* y, double* y_next) {
  const int n = state_size();
  double* stage = stage_.data();
  if (const int code = rhs().Evaluate(t, y, k1_.data()); code != 0) return code;
  for (int i = 0; i < n; ++i) stage[i] = y[i] + 0.5 * h * k1_[i];
  if (const int code = rhs().Evaluate(t + 0.5 * h, stage, k2_.data()); code != 0) return code;
  for (int i = 0; i < n; ++i) stage[i] = y[i] + 0.5 * h * k2_[i];
  if (const int code = rhs().Evaluate(t + 0.5 * h, stage, k3_.data()); code != 0) return code;
  for (int i = 0; i < n; ++i) stage[i] = y[i] + h * k3_[i];
  if (const int code = rhs().Evaluate(t + h, stage, k4_.data()); code != 0) return code;
  for (int i = 0; i < n; ++i) {
    y_next[i] = y[i] + h / 6.0 * (k1_[i] + 2.0 * k2_[i] + 2.0 * k3_[i] + k4_[i]);
  }
  return 0;
}

}  // namespace mbstream
