// IDA: variable-order BDF for differential-algebraic systems F(t, y, y') = 0, with Newton
// iteration on a sparse (SUNDIALS KLU) or dense iteration matrix filled by coloured finite
// differences over the system's known sparsity.
#pragma once

#include <memory>
#include <vector>

#include "server/integrate/ida_colored_jacobian.h"
#include "server/integrate/ida_system.h"
#include "server/integrate/integrator_base.h"
#include "server/integrate/sundials_callbacks.h"
#include "server/integrate/sundials_handles.h"

namespace mbstream {

struct IdaOptions {
  IntegratorOptions base;  // tolerances, max step, step budget, stop time (method kIda)
  enum class LinearSolver {
    kKlu,    // SUNLinSol_KLU on a SUNSparseMatrix with the system's pattern
    kDense,  // SUNLinSol_Dense (the fallback; O(n^3) per factorisation)
  };
  LinearSolver linear_solver = LinearSolver::kKlu;
  // Leave the algebraic unknowns (id = 0) out of the local error test (IDASetSuppressAlg),
  // the usual treatment of the multipliers of index-2 and index-3 systems.
  bool suppress_algebraic = true;
  // s, the smallest step IDA may take (IDASetMinStep): a time-independent bound on how far
  // the step size may collapse before the run stops. 0 = 1e-12 * max(1, |t_final|).
  double min_step = 0.0;
  // s, the first step to try (IDASetInitStep); 0 = IDA's own estimate, which for stiff
  // index-2 systems at tight tolerances can be so small that the iteration matrix is too
  // ill-conditioned for Newton to converge.
  double initial_step = 0.0;
};

namespace sundials {

// What IDA's callbacks reach through user_data: the system with its checks and counters.
class IdaCallbacks {
 public:
  IdaCallbacks(DaeSystem& system, double divergence_limit);

  // F(t, y, yp) with the checks: a diverged y is an unrecoverable failure, a non-finite
  // residual a recoverable one (the Newton iterate was wild; IDA retries with a smaller
  // step). An exception from the system is an unrecoverable failure whose message is kept
  // (none crosses IDA's C frames). Allocates nothing.
  int Residual(double t, const double* y, const double* yp, double* r) noexcept;

  // Records an exception `what` at time t as the event (the first is kept) and returns the
  // unrecoverable code for IDA. For the C callbacks' boundary.
  int RecordException(double t, const char* what) noexcept;

  DaeSystem& system() { return system_; }
  ColoredJacobian& jacobian() { return jacobian_; }
  long num_residual_evals() const { return num_evals_ + jacobian_.num_residual_evals(); }
  const char* event() const { return event_; }  // "" when nothing happened
  void* solver = nullptr;                       // the IDA memory
  bool dense = false;                           // fill a SUNDenseMatrix, not a sparse one
  std::vector<double> values;                   // one per pattern entry (dense path)

 private:
  DaeSystem& system_;
  double divergence_limit_;
  ColoredJacobian jacobian_;
  long num_evals_ = 0;
  char event_[320] = {};
};

class IdaIntegrator final : public IntegratorBase, private ChunkedSolver {
 public:
  // (t0, y0, yp0) must be consistent: F(t0, y0, yp0) = 0 (the caller computes it).
  IdaIntegrator(DaeSystem& system, double t0, const double* y0, const double* yp0,
                const IdaOptions& options);
  ~IdaIntegrator() override;

  SolverStats stats() const override;
  const char* name() const override;
  int num_colors() const { return callbacks_.jacobian().num_colors(); }
  // y' at the last successful output.
  const double* derivative() const;

 private:
  AdvanceResult DoAdvance(double t_out, double* y) override;
  MethodKind method_kind() const override { return MethodKind::kImplicit; }
  long NumSteps() const override;
  double CurrentTime() const override;
  void LimitSteps(long steps) override;
  int Solve(double t_out, double* t_reached) override;
  int TooMuchWorkFlag() const override;
  void CheckSetup(int flag, const char* call) const;

  mutable IdaCallbacks callbacks_;
  IdaOptions ida_options_;
  ErrorSink errors_;
  Context context_;
  Vector y0_, yp0_, id_, yp_out_;
  Vector out_;  // wraps the caller's output buffer
  Matrix matrix_;
  LinearSolver linear_solver_;
  void* memory_ = nullptr;
  double min_step_ = 0.0;
};

}  // namespace sundials

// Validates the options (tolerances as for the ODE methods) and creates the integrator.
// Throws InputError for invalid options.
std::unique_ptr<sundials::IdaIntegrator> MakeIdaIntegrator(DaeSystem& system, double t0,
                                                           const double* y0, const double* yp0,
                                                           const IdaOptions& options);

}  // namespace mbstream
