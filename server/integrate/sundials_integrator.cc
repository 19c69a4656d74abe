#include "server/integrate/sundials_integrator.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <arkode/arkode.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>

#include "server/integrate/failure_messages.h"
#include "server/integrate/fast_serial_ops.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream::sundials {

namespace {

Context CreateContext() {
  SUNContext context = nullptr;
  MBSTREAM_CHECK_MSG(SUNContext_Create(nullptr, &context) == 0 && context != nullptr,
                     "SUNContext_Create failed");
  return Context(context);
}

}  // namespace

SundialsIntegrator::SundialsIntegrator(OdeSystem& system, double t0, const double* y0,
                                       const IntegratorOptions& options, Family family,
                                       bool implicit, bool fixed_point)
    : IntegratorBase(system.size(), t0, y0, options),
      rhs_(system, options.divergence_limit, options.error_states),
      callback_data_{
          &rhs_,
          nullptr,
          family,
          system.HasJacobian(),
          options.rtol,
          options.atol,
          options.error_states > 0 ? std::min(options.error_states, system.size()) : system.size()},
      family_(family),
      implicit_(implicit),
      fixed_point_(fixed_point),
      context_(CreateContext()) {
  const int n = system.size();
  y0_.reset(N_VNew_Serial(n, context()));
  CheckCreated(y0_.get(), "N_VNew_Serial");
  // CVODE only: its vectors are clones of y0_ and inherit the table. (ARKODE's ERK would
  // take other, differently rounded paths through the fused operations: left as it was,
  // but for the error norm, which leaves appended quadratures out, fast_serial_ops.h.)
  if (family == Family::kCvode) {
    InstallFastSerialOps(y0_.get());
  } else {
    InstallErrorNorm(y0_.get());
  }
  std::copy(y0, y0 + n, N_VGetArrayPointer(y0_.get()));
  out_.reset(N_VMake_Serial(n, nullptr, context()));
  CheckCreated(out_.get(), "N_VMake_Serial");
  if (family == Family::kCvode) {
    InstallFastSerialOps(out_.get());
  } else {
    InstallErrorNorm(out_.get());
  }
}

void SundialsIntegrator::CheckSetup(int flag, const char* call) const {
  if (flag >= 0) return;
  MBSTREAM_CHECK_MSG(false, FormatString("%s returned %d (%s)", call, flag, errors_.message()));
}

void SundialsIntegrator::CheckCreated(const void* object, const char* call) const {
  MBSTREAM_CHECK_MSG(object != nullptr, FormatString("%s failed", call));
}

bool SundialsIntegrator::Retune(const IntegratorOptions& next) {
  const IntegratorOptions& now = options();
  if (failed() || next.method != now.method || next.erk_table != now.erk_table ||
      next.max_step != now.max_step || next.divergence_limit != now.divergence_limit ||
      !(next.t_final >= last_time()) || !(next.rtol > 0.0) || !(next.atol > 0.0)) {
    return false;
  }
  IntegratorOptions options = next;
  options.error_states = now.error_states;
  options.max_steps = NumSteps() + next.max_steps;
  if (std::isfinite(options.t_final)) CheckSetup(SetStopTime(options.t_final), "SetStopTime");
  callback_data_.rtol = options.rtol;
  callback_data_.atol = options.atol;
  ReplaceOptions(options);
  return true;
}

bool SundialsIntegrator::DoRestart(double t0, const double* y0, const IntegratorOptions& next) {
  if (!(next.rtol > 0.0) || !(next.atol > 0.0)) return false;
  std::copy(y0, y0 + state_size(), N_VGetArrayPointer(y0_.get()));
  rhs_.Reset();
  errors_.Clear();
  callback_data_.rtol = next.rtol;
  callback_data_.atol = next.atol;
  CheckSetup(ReInit(t0), "ReInit");
  if (std::isfinite(next.t_final)) CheckSetup(SetStopTime(next.t_final), "SetStopTime");
  return true;
}

int SundialsIntegrator::TooMuchWorkFlag() const {
  return family_ == Family::kCvode ? CV_TOO_MUCH_WORK : ARK_TOO_MUCH_WORK;
}

AdvanceResult SundialsIntegrator::DoAdvance(double t_out, double* y) {
  errors_.Clear();
  N_VSetArrayPointer(y, out_.get());
  const ChunkedSolve solve = SolveInChunks(t_out, y, *this);
  if (solve.flag >= 0) return {IntegratorStatus::kOk, t_out, {}};
  double t_reached = solve.t_reached;
  if (solve.evolved && family_ == Family::kArkode && solve.flag != ARK_TOO_MUCH_WORK) {
    // When a step fails ARKODE 6.4 returns the last step's state with the time of the
    // failed stage (tcur), not the step's: the pair is inconsistent. Use the last output.
    // (The step budget runs out between steps, where the pair is consistent.)
    t_reached = last_time();
    std::copy(last_state(), last_state() + state_size(), y);
  }
  FailureContext context{family_,      solve.flag,       name(), implicit_,
                         fixed_point_, t_reached,        t_out,  options().max_steps,
                         &rhs_,        errors_.message()};
  AdvanceResult result = FailureResult(context);
  if (solve.cpu_spent) result.message = CpuBudgetMessage(name(), result.t, t_out);
  return result;
}

}  // namespace mbstream::sundials
