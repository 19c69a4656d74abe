// Semi-implicit (symplectic) Euler with a fixed step, the game-engine baseline, for a
// second-order system y = [x; v; rest] with x' = v (OdeSystem::num_positions() = size of x):
//   v+ = v + h a(t, x, v);  x+ = x + h v+;  rest+ = rest + h rest'(t, y),
// or x+ = x + h G(x) v+ for a system whose positions' rate is its own (OdeSystem::PositionRate:
// quaternions).
#pragma once

#include <vector>

#include "server/integrate/fixed_step_integrator.h"

namespace mbstream {

class SemiImplicitEulerIntegrator final : public FixedStepIntegrator {
 public:
  // system.num_positions() must be > 0 and num_positions() + num_velocities() <= size().
  SemiImplicitEulerIntegrator(OdeSystem& system, double t0, const double* y0,
                              const IntegratorOptions& options);

  const char* name() const override { return "fixed-step semi-implicit Euler"; }

 private:
  int Step(double t, double h, const double* y, double* y_next) override;

  int num_positions_;
  bool own_rate_;  // positions whose rate is not their velocities (OdeSystem::PositionRate)
  std::vector<double> ydot_;
  std::vector<double> x_rate_;
};

}  // namespace mbstream
