#include "server/integrate/arkstep_integrator.h"

#include <cmath>

#include <arkode/arkode_arkstep.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <exception>

#include "server/integrate/manifold_projection.h"

namespace mbstream::sundials {

namespace {

// In SUNDIALS 6.4 ARKStep's Newton iteration with an iteration matrix I - gamma J built for
// an older step size returns stage values far less accurate than the tolerances (an error of
// 1e-3 at rtol 1e-6 on a harmonic oscillator). Rebuilding the matrix (from the same
// Jacobian: no extra right-hand side evaluations) whenever gamma changes at all avoids it.
constexpr double kDeltaGammaMax = 1e-8;

void* CreateArkStep(ArkStepIntegrator::Variant variant, double t0, N_Vector y0,
                    SUNContext context) {
  const bool implicit = variant == ArkStepIntegrator::Variant::kDirk;
  return ARKStepCreate(implicit ? nullptr : RhsCallback, implicit ? RhsCallback : nullptr, t0, y0,
                       context);
}

// ARKPostProcessFn: the system's in-place projection after each step (one-step methods start
// the next step from the projected state).
int ProjectStepCallback(sunrealtype t, N_Vector y, void* user_data) noexcept {
  auto* data = static_cast<CallbackData*>(user_data);
  try {
    return EveryStepProjectionOf(data->rhs->system())->ProjectInPlace(t, N_VGetArrayPointer(y));
  } catch (const std::exception& error) {
    return data->rhs->RecordException(t, error.what());
  }
}

}  // namespace

ArkStepIntegrator::ArkStepIntegrator(Variant variant, OdeSystem& system, double t0,
                                     const double* y0, const IntegratorOptions& options)
    : SundialsIntegrator(system, t0, y0, options, Family::kArkode,
                         /*implicit=*/variant == Variant::kDirk, /*fixed_point=*/false),
      variant_(variant),
      table_(variant == Variant::kDirk ? FindDirkTable(options.erk_table)
                                       : FindErkTable(options.erk_table)),
      name_(std::string(variant == Variant::kDirk ? "ARKODE DIRK (" : "ARKODE ERK (") +
            table_.display + ")"),
      memory_(CreateArkStep(variant, t0, initial_state(), context()), ARKStepFree) {
  void* ark = memory_.get();
  CheckCreated(ark, "ARKStepCreate");
  CheckSetup(ARKStepSetErrHandlerFn(ark, ErrorSink::Handle, &errors()), "ARKStepSetErrHandlerFn");
  callback_data().solver = ark;
  CheckSetup(ARKStepSetUserData(ark, &callback_data()), "ARKStepSetUserData");
  if (variant == Variant::kDirk) {
    CheckSetup(ARKStepSetTableNum(ark, static_cast<ARKODE_DIRKTableID>(table_.id), ARKODE_ERK_NONE),
               "ARKStepSetTableNum");
  } else {
    CheckSetup(ARKStepSetTableNum(ark, ARKODE_DIRK_NONE, static_cast<ARKODE_ERKTableID>(table_.id)),
               "ARKStepSetTableNum");
  }
  // The weights from callback_data() (its tolerances), so that Retune can change them.
  CheckSetup(ARKStepWFtolerances(ark, ErrorWeightCallback), "ARKStepWFtolerances");
  if (options.max_step > 0.0) {
    CheckSetup(ARKStepSetMaxStep(ark, options.max_step), "ARKStepSetMaxStep");
  }
  if (std::isfinite(options.t_final)) {
    CheckSetup(ARKStepSetStopTime(ark, options.t_final), "ARKStepSetStopTime");
  }
  if (system.num_roots() > 0) {
    CheckSetup(ARKStepRootInit(ark, system.num_roots(), RootCallback), "ARKStepRootInit");
    CheckSetup(ARKStepSetNoInactiveRootWarn(ark), "ARKStepSetNoInactiveRootWarn");
  }
  if (EveryStepProjectionOf(system) != nullptr) {
    CheckSetup(ARKStepSetPostprocessStepFn(ark, ProjectStepCallback),
               "ARKStepSetPostprocessStepFn");
  }
  if (variant == Variant::kDirk) {
    const int n = system.size();
    matrix_.reset(SUNDenseMatrix(n, n, context()));
    CheckCreated(matrix_.get(), "SUNDenseMatrix");
    linear_solver_.reset(SUNLinSol_Dense(initial_state(), matrix_.get(), context()));
    CheckCreated(linear_solver_.get(), "SUNLinSol_Dense");
    CheckSetup(ARKStepSetLinearSolver(ark, linear_solver_.get(), matrix_.get()),
               "ARKStepSetLinearSolver");
    CheckSetup(ARKStepSetJacFn(ark, DenseJacobianCallback), "ARKStepSetJacFn");
    CheckSetup(ARKStepSetDeltaGammaMax(ark, kDeltaGammaMax), "ARKStepSetDeltaGammaMax");
  }
}

long ArkStepIntegrator::NumSteps() const {
  long steps = 0;
  ARKStepGetNumSteps(memory_.get(), &steps);
  return steps;
}

double ArkStepIntegrator::CurrentTime() const {
  double t = 0.0;
  ARKStepGetCurrentTime(memory_.get(), &t);
  return t;
}

int ArkStepIntegrator::SetMaxNumSteps(long steps) {
  return ARKStepSetMaxNumSteps(memory_.get(), steps);
}

int ArkStepIntegrator::Evolve(double t_out, N_Vector y, double* t_reached) {
  int flag = ARK_ROOT_RETURN;
  while (flag == ARK_ROOT_RETURN) {  // a root ends the step there; go on to t_out
    flag = ARKStepEvolve(memory_.get(), t_out, y, t_reached, ARK_NORMAL);
    if (flag == ARK_ROOT_RETURN) ++roots_found_;
  }
  return flag;
}

int ArkStepIntegrator::SetStopTime(double t_final) {
  return ARKStepSetStopTime(memory_.get(), t_final);
}

int ArkStepIntegrator::ReInit(double t0) {
  roots_found_ = 0;
  const bool implicit = variant_ == Variant::kDirk;
  return ARKStepReInit(memory_.get(), implicit ? nullptr : RhsCallback,
                       implicit ? RhsCallback : nullptr, t0, initial_state());
}

SolverStats ArkStepIntegrator::stats() const {
  void* ark = memory_.get();
  SolverStats stats;
  ARKStepGetNumSteps(ark, &stats.steps);
  stats.rhs_evals = rhs().num_evals();
  ARKStepGetNumErrTestFails(ark, &stats.error_test_failures);
  ARKStepGetLastStep(ark, &stats.last_step);
  stats.last_order = table_.order;
  stats.roots_found = roots_found_;
  if (variant_ == Variant::kDirk) {
    ARKStepGetNumJacEvals(ark, &stats.jac_evals);
    ARKStepGetNumNonlinSolvIters(ark, &stats.nonlinear_iterations);
    ARKStepGetNumNonlinSolvConvFails(ark, &stats.convergence_failures);
  }
  return stats;
}

}  // namespace mbstream::sundials
