// What the fixed-step methods share: a step grid t_k = t0 + k h that does not depend on the
// output times, and exact outputs in between. The state is advanced from grid point to grid
// point; an output time between two grid points gets a partial step from the grid point
// before it, written to the output only, so the outputs never perturb the grid.
#pragma once

#include <vector>

#include "server/integrate/integrator_base.h"
#include "server/integrate/manifold_projection.h"
#include "server/integrate/rhs_adapter.h"

namespace mbstream {

class FixedStepIntegrator : public IntegratorBase {
 public:
  SolverStats stats() const override;

 protected:
  FixedStepIntegrator(OdeSystem& system, double t0, const double* y0,
                      const IntegratorOptions& options, int order);

  // One step of size h from (t, y) into y_next (y_next != y). Returns 0, or the failing
  // code of RhsAdapter::Evaluate. Must not allocate.
  virtual int Step(double t, double h, const double* y, double* y_next) = 0;

  RhsAdapter& rhs() { return rhs_; }
  MethodKind method_kind() const final { return MethodKind::kFixedStep; }

 private:
  AdvanceResult DoAdvance(double t_out, double* y) final;
  bool DoRestart(double t0, const double* y0, const IntegratorOptions& options) final;
  double GridTime(long k) const { return t0_ + static_cast<double>(k) * step_; }
  // The result of a failed step from grid point k (y = the state there).
  AdvanceResult StepFailure(int code, double t, double h, double* y);

  // Projects y_next after a step (EveryStepProjectionOf the system); 0 or its failing code.
  int ProjectStep(double t, double* y_next);

  RhsAdapter rhs_;
  ManifoldProjection* const projection_;  // null: nothing to project
  double t0_;
  double step_;
  int order_;
  long k_ = 0;  // the grid point of y_grid_
  std::vector<double> y_grid_;
  std::vector<double> y_next_;
  long steps_ = 0;            // grid steps (the partial steps to outputs are not counted)
  long cpu_chunk_start_ = 0;  // steps_ at the last check of the CPU budget
  long next_cpu_check_ = 0;   // steps_ at which the CPU budget is checked next
  double last_step_ = 0.0;
};

}  // namespace mbstream
