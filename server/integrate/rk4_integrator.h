// The classical fourth-order Runge-Kutta method with a fixed step (no SUNDIALS).
#pragma once

#include <vector>

#include "server/integrate/fixed_step_integrator.h"

namespace mbstream {

class Rk4Integrator final : public FixedStepIntegrator {
 public:
  Rk4Integrator(OdeSystem& system, double t0, const double* y0, const IntegratorOptions& options);

  const char* name() const override { return "fixed-step RK4"; }

 private:
  int Step(double t, double h, const double* y, double* y_next) override;

  std::vector<double> k1_, k2_, k3_, k4_, stage_;
};

}  // namespace mbstream
