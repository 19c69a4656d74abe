#include "server/integrate/integrator.h"

#include <cmath>
#include <string>

#include "server/integrate/appended_quadratures.h"
#include "server/integrate/arkstep_integrator.h"
#include "server/integrate/butcher_tables.h"
#include "server/integrate/cvode_integrator.h"
#include "server/integrate/failure_messages.h"
#include "server/integrate/rk4_integrator.h"
#include "server/integrate/semi_implicit_euler_integrator.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

bool IsAdaptive(Method method) {
  return method == Method::kBdf || method == Method::kAdams || method == Method::kErk ||
         method == Method::kDirk || method == Method::kIda;
}

// What CheckIntegratorOptions cannot know: the system, the start time and state.
void CheckStart(const OdeSystem& system, double t0, const double* y0,
                const IntegratorOptions& options) {
  MBSTREAM_CHECK_MSG(system.size() > 0 && y0 != nullptr, "an ODE system needs states");
  if (!std::isfinite(t0) || std::isnan(options.t_final) || !(options.t_final > t0)) {
    throw InputError(FormatString(
        "integrator: the end time t_final = %g s must come after the start time t0 = %g s "
        "(check the run's duration)",
        options.t_final, t0));
  }
  for (int i = 0; i < system.size(); ++i) {
    if (!std::isfinite(y0[i])) {
      throw InputError(FormatString(
          "integrator: the initial state is not finite (component %d is %g); check the "
          "initial positions and velocities",
          i, y0[i]));
    }
  }
}

}  // namespace

const char* IntegratorStatusName(IntegratorStatus status) {
  switch (status) {
    case IntegratorStatus::kOk:
      return "ok";
    case IntegratorStatus::kDiverged:
      return "diverged";
    case IntegratorStatus::kTooMuchWork:
      return "too_much_work";
    case IntegratorStatus::kErrorTestFailures:
      return "error_test_failures";
    case IntegratorStatus::kConvergenceFailures:
      return "convergence_failures";
    case IntegratorStatus::kRhsFailure:
      return "rhs_failure";
    case IntegratorStatus::kSetupFailure:
      return "setup_failure";
  }
  return "unknown";
}

void CheckIntegratorOptions(const IntegratorOptions& options) {
  const char* method = MethodName(options.method);
  if (IsAdaptive(options.method)) {
    if (!(options.rtol > 0.0 && options.rtol < 1.0)) {
      throw InputError(FormatString(
          "rtol = %g: the relative tolerance of method %s must be in (0, 1), e.g. 1e-6",
          options.rtol, method));
    }
    if (!(options.atol >= 0.0 && std::isfinite(options.atol))) {
      throw InputError(FormatString(
          "atol = %g: the absolute tolerance of method %s must be finite and >= 0, e.g. 1e-8",
          options.atol, method));
    }
    if (!(options.max_step >= 0.0 && std::isfinite(options.max_step))) {
      throw InputError(FormatString("max_step = %g s: must be finite and >= 0 (0 = no limit)",
                                    options.max_step));
    }
  } else if (!(options.fixed_step > 0.0 && std::isfinite(options.fixed_step))) {
    throw InputError(
        FormatString("fixed_step = %g s: the step of method %s must be finite and > 0, e.g. 1e-3",
                     options.fixed_step, method));
  }
  if (options.max_steps <= 0) {
    throw InputError(
        FormatString("max_steps = %ld: must be > 0, e.g. 10000000", options.max_steps));
  }
  MBSTREAM_CHECK_MSG(options.divergence_limit > 0.0, "divergence_limit must be > 0");
  if (options.method == Method::kErk) {
    FindErkTable(options.erk_table);  // throws InputError for an unknown name
  } else if (options.method == Method::kDirk) {
    FindDirkTable(options.erk_table);  // throws InputError for an unknown name
  } else if (!options.erk_table.empty()) {
    throw InputError("erk_table '" + options.erk_table +
                     "': a Butcher table applies only to methods erk and dirk, not to " + method +
                     "; leave it empty or choose method erk or dirk");
  }
}

std::unique_ptr<Integrator> MakeIntegrator(OdeSystem& system, double t0, const double* y0,
                                           const IntegratorOptions& options) {
  CheckIntegratorOptions(options);
  CheckStart(system, t0, y0, options);
  if (system.num_quadratures() > 0) {
    return MakeAppendedQuadratureIntegrator(system, t0, y0, options);
  }
  using sundials::ArkStepIntegrator;
  using sundials::CvodeIntegrator;
  switch (options.method) {
    case Method::kBdf:
      return std::make_unique<CvodeIntegrator>(CvodeIntegrator::Variant::kBdf, system, t0, y0,
                                               options);
    case Method::kAdams:
      return std::make_unique<CvodeIntegrator>(CvodeIntegrator::Variant::kAdams, system, t0, y0,
                                               options);
    case Method::kErk:
      return std::make_unique<ArkStepIntegrator>(ArkStepIntegrator::Variant::kErk, system, t0, y0,
                                                 options);
    case Method::kDirk:
      return std::make_unique<ArkStepIntegrator>(ArkStepIntegrator::Variant::kDirk, system, t0, y0,
                                                 options);
    case Method::kRk4:
      return std::make_unique<Rk4Integrator>(system, t0, y0, options);
    case Method::kEuler: {
      const int np = system.num_positions();
      if (np <= 0) {
        throw InputError(
            "method euler (semi-implicit Euler) needs a second-order system y = [x; v] with "
            "x' = v, and this one is not (num_positions() == 0): use rk4 or an adaptive "
            "method (bdf, adams, erk, dirk)");
      }
      MBSTREAM_CHECK_MSG(np + system.num_velocities() <= system.size(),
                         "num_positions() + num_velocities() is more than the state size");
      return std::make_unique<SemiImplicitEulerIntegrator>(system, t0, y0, options);
    }
    case Method::kIda:
      throw InputError(
          "method ida solves differential-algebraic equations and this system is an ODE: "
          "use a DAE formulation for ida, or an ODE method (bdf, adams, erk, dirk, rk4, euler)");
  }
  throw InputError("unknown integration method");
}

}  // namespace mbstream
