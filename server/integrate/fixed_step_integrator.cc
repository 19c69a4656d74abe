#include "server/integrate/fixed_step_integrator.h"

#include <algorithm>
#include <exception>
#include <utility>

#include "server/integrate/failure_messages.h"
#include "server/integrate/state_health.h"
#include "shared/common/format.h"

namespace mbstream {

FixedStepIntegrator::FixedStepIntegrator(OdeSystem& system, double t0, const double* y0,
                                         const IntegratorOptions& options, int order)
    : IntegratorBase(system.size(), t0, y0, options),
      rhs_(system, options.divergence_limit, options.error_states),
      projection_(EveryStepProjectionOf(system)),
      t0_(t0),
      step_(options.fixed_step),
      order_(order),
      y_grid_(y0, y0 + system.size()),
      y_next_(system.size()) {}

int FixedStepIntegrator::ProjectStep(double t, double* y_next) {
  if (projection_ == nullptr) return 0;
  try {
    return projection_->ProjectInPlace(t, y_next);
  } catch (const std::exception& error) {
    return rhs_.RecordException(t, error.what());
  }
}

AdvanceResult FixedStepIntegrator::StepFailure(int code, double t, double h, double* y) {
  std::copy(y_grid_.begin(), y_grid_.end(), y);
  if (rhs_.event() != RhsAdapter::Event::kNone)
    return RhsEventResult(name(), rhs_, t, MethodKind::kFixedStep);
  if (code > 0) {
    return {IntegratorStatus::kRhsFailure, t,
            FormatString("%s: the model's right-hand side failed recoverably (code %d) at t = "
                         "%.9g s, and a fixed-step method cannot retry with a smaller step: "
                         "use a smaller step (--step) or an adaptive method (bdf, erk)",
                         name(), code, rhs_.last_recoverable_time())};
  }
  // The step's result was not healthy (its stages were).
  return {IntegratorStatus::kDiverged, t,
          DivergedMessage(name(), t + h, options().divergence_limit, MethodKind::kFixedStep)};
}

AdvanceResult FixedStepIntegrator::DoAdvance(double t_out, double* y) {
  const int n = state_size();
  const double limit = options().divergence_limit;
  // Output times within this of a grid point are taken to be on it.
  const double on_grid = 1e-9 * step_;
  while (GridTime(k_ + 1) <= t_out + on_grid) {
    const double t = GridTime(k_);
    if (steps_ >= options().max_steps) {
      std::copy(y_grid_.begin(), y_grid_.end(), y);
      return {IntegratorStatus::kTooMuchWork, t,
              TooMuchWorkMessage(name(), options().max_steps, t, t_out, false)};
    }
    if (steps_ >= next_cpu_check_) {
      if (CpuDeadlinePassed()) {
        std::copy(y_grid_.begin(), y_grid_.end(), y);
        return {IntegratorStatus::kTooMuchWork, t, CpuBudgetMessage(name(), t, t_out)};
      }
      CpuCheckPacer& pacer = cpu_check_pacer();
      pacer.Finish(steps_ - cpu_chunk_start_);
      pacer.Start();
      cpu_chunk_start_ = steps_;
      next_cpu_check_ = steps_ + pacer.Chunk(options().max_steps);
    }
    // The last grid point may lie a rounding error beyond t_final: never step past it.
    const double h = std::min(GridTime(k_ + 1), options().t_final) - t;
    int code = Step(t, h, y_grid_.data(), y_next_.data());
    if (code == 0) code = ProjectStep(t + h, y_next_.data());
    if (code != 0 ||
        !IsHealthyState(y_next_.data(), n, LimitedStates(n, options().error_states), limit)) {
      return StepFailure(code, t, h, y);
    }
    std::swap(y_grid_, y_next_);
    ++k_;
    ++steps_;
    last_step_ = h;
  }

  const double t_grid = GridTime(k_);
  if (t_out - t_grid <= on_grid) {
    std::copy(y_grid_.begin(), y_grid_.end(), y);
    return {IntegratorStatus::kOk, t_out, {}};
  }
  // A partial step to the output time, from the grid point before it.
  int code = Step(t_grid, t_out - t_grid, y_grid_.data(), y);
  if (code == 0) code = ProjectStep(t_out, y);
  if (code != 0) return StepFailure(code, t_grid, t_out - t_grid, y);
  return {IntegratorStatus::kOk, t_out, {}};
}

bool FixedStepIntegrator::DoRestart(double t0, const double* y0,
                                    const IntegratorOptions& /*options*/) {
  rhs_.Reset();
  t0_ = t0;
  k_ = 0;
  std::copy(y0, y0 + state_size(), y_grid_.begin());
  steps_ = 0;
  cpu_chunk_start_ = 0;
  next_cpu_check_ = 0;
  last_step_ = 0.0;
  return true;
}

SolverStats FixedStepIntegrator::stats() const {
  SolverStats stats;
  stats.steps = steps_;
  stats.rhs_evals = rhs_.num_evals();
  stats.last_step = last_step_;
  stats.last_order = order_;
  return stats;
}

}  // namespace mbstream
