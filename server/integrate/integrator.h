// The time-integration layer: advances an OdeSystem to requested output times with one of
// the methods of the contract (SUNDIALS CVODE/ARKODE, fixed-step RK4, semi-implicit Euler).
// It knows nothing of mechanics.
#pragma once

#include <limits>
#include <memory>
#include <string>

#include "server/integrate/method.h"
#include "server/integrate/ode_system.h"

namespace mbstream {

struct IntegratorOptions {
  Method method = Method::kBdf;
  double rtol = 1e-6;        // relative tolerance (adaptive methods)
  double atol = 1e-8;        // absolute tolerance, same for every state (adaptive methods)
  double max_step = 0.0;     // s, largest internal step of adaptive methods; 0 = none
  double fixed_step = 1e-3;  // s, the step of kRk4 and kEuler
  // ARKODE table: for kErk an explicit table, for kDirk a diagonally implicit one ("" = the
  // method's default). See ErkTableNames() / DirkTableNames() in butcher_tables.h.
  std::string erk_table;
  long max_steps = 10'000'000;  // internal steps in total, over all AdvanceTo calls
  // s, the calling thread's CPU clock (ThreadCpuSeconds) at which the integration stops
  // with kTooMuchWork: the run's CPU budget. Checked between chunks of internal steps
  // (CpuCheckPacer: about every 10 ms, at most 256 steps apart).
  // Infinity = no CPU budget.
  double cpu_deadline_s = std::numeric_limits<double>::infinity();
  // s, the integrator never steps past it (CVodeSetStopTime etc.); AdvanceTo may not ask
  // for a later time. Infinity = no stop time.
  double t_final = std::numeric_limits<double>::infinity();
  double divergence_limit = 1e10;  // |y_i| beyond this (or non-finite) = diverged
  // States under error control: the first `error_states` of y (0 = all). The rest get a
  // zero error weight (the appended quadrature states; see OdeSystem::num_quadratures).
  int error_states = 0;
};

// Checks the options alone, before any system exists: tolerances, steps and the step budget
// for the method, and the Butcher table (known for erk and dirk, absent for the others).
// Throws InputError saying what is wrong and what to give instead. MakeIntegrator and
// MakeIdaIntegrator call it; a run's validation calls it before the run is queued.
void CheckIntegratorOptions(const IntegratorOptions& options);

// Cumulative solver statistics since creation.
struct SolverStats {
  long steps = 0;                 // accepted internal steps
  long rhs_evals = 0;             // calls of OdeSystem::Rhs, including finite-difference Jacobians
  long jac_evals = 0;             // Jacobian evaluations (own or finite-difference)
  long nonlinear_iterations = 0;  // Newton or fixed-point iterations
  long error_test_failures = 0;
  long convergence_failures = 0;  // nonlinear solver convergence failures
  double last_step = 0.0;         // s, the last internal step size taken
  int last_order = 0;             // method order used on the last step
  long roots_found = 0;           // root returns (OdeSystem::Roots changed sign; CVODE, ARKODE)
};

enum class IntegratorStatus {
  kOk,
  kDiverged,             // the state became non-finite or exceeded the divergence limit
  kTooMuchWork,          // the max_steps budget (or the cpu_deadline_s budget) ran out
  kErrorTestFailures,    // the local error test failed repeatedly / accuracy unreachable
  kConvergenceFailures,  // the nonlinear or linear solver failed repeatedly
  kRhsFailure,           // OdeSystem::Rhs failed (or returned non-finite derivatives)
  kSetupFailure,         // bad input to the solver or an internal solver failure
};

// "ok", "diverged", "too_much_work", ...
const char* IntegratorStatusName(IntegratorStatus status);

struct AdvanceResult {
  IntegratorStatus status = IntegratorStatus::kOk;
  double t = 0.0;       // s, the time reached (the last good time on failure)
  std::string message;  // on failure: what happened, when, and what to try; empty when ok
};

class Integrator {
 public:
  virtual ~Integrator() = default;

  // Advances to exactly t_out (t_out >= the previous output time, t_out <= t_final) and
  // writes y(t_out) into y (size() doubles). Adaptive methods interpolate inside their last
  // step: they are not stopped at each output. On failure status != kOk, `t` is the last
  // good time and y the (finite) state there; later calls return the same failure. Does not
  // allocate on the heap after the first call when it succeeds.
  virtual AdvanceResult AdvanceTo(double t_out, double* y) = 0;

  virtual SolverStats stats() const = 0;

  // The system's quadratures (OdeSystem::num_quadratures) at the last time AdvanceTo
  // reached, from their initial values 0, into q. Returns false, writing nothing, when the
  // system has none.
  virtual bool Quadratures(double* /*q*/) { return false; }

  // e.g. "CVODE BDF", "ARKODE ERK (Dormand-Prince 7-4-5)", "fixed-step RK4".
  virtual const char* name() const = 0;

  // Goes on from the last output with other tolerances, stop time and budgets (rtol, atol,
  // t_final, cpu_deadline_s; max_steps counted from now), keeping the method's step size and
  // order: a run continuing a pilot does not start again at order 1 with tiny steps. The
  // method, table, max_step and divergence limit must be those it was made with. Returns
  // false, changing nothing, when it cannot (a fixed-step method, another method, a failed
  // integration, t_final before the last output).
  virtual bool Retune(const IntegratorOptions& /*options*/) { return false; }

  // Starts again at (t0, y0), as MakeIntegrator(system, t0, y0, options) would, in this one's
  // memory: no heap allocation (CVodeReInit / ARKStepReInit for SUNDIALS' methods). Its
  // statistics and quadratures start from zero again, and no step straddles t0 (the use: a
  // discontinuity at t0, such as a new command held from then on). `options` may change
  // t_final (finite, after t0, and finite already if it was), the tolerances, max_steps and
  // cpu_deadline_s; the method, table, fixed step, max_step, divergence limit and error
  // states must be those it was made with. Returns false, changing nothing, when they are not
  // or y0 is not finite: make a new integrator then.
  virtual bool Restart(double /*t0*/, const double* /*y0*/, const IntegratorOptions& /*options*/) {
    return false;
  }
};

// Creates the integrator for `system` starting at (t0, y0); keeps a reference to `system`,
// which must outlive it. Throws InputError for an unsupported combination (kIda, which is
// not an ODE method; kEuler on a system with num_positions() == 0), an unknown table name
// (the message lists the accepted ones) or invalid options.
std::unique_ptr<Integrator> MakeIntegrator(OdeSystem& system, double t0, const double* y0,
                                           const IntegratorOptions& options);

}  // namespace mbstream
