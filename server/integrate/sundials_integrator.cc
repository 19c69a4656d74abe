#include "server/integrate/sundials_integrator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <arkode/arkode.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>

#include "common/check.h"
#include "common/format.h"
#include "server/integrate/failure_messages.h"
#include "server/integrate/fast_serial_ops.h"

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
      rhs_(system, options.divergence_limit),
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
  // take other, differently rounded paths through the fused operations: left as it was.)
  if (family == Family::kCvode) InstallFastSerialOps(y0_.get());
  std::copy(y0, y0 + n, N_VGetArrayPointer(y0_.get()));
  out_.reset(N_VMake_Serial(n, nullptr, context()));
  CheckCreated(out_.get(), "N_VMake_Serial");
  if (family == Family::kCvode) InstallFastSerialOps(out_.get());
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

AdvanceResult SundialsIntegrator::DoAdvance(double t_out, double* y) {
  errors_.Clear();
  N_VSetArrayPointer(y, out_.get());

  // max_steps is a budget over the whole run; the solvers count per call. With a CPU budget
  // the solver is called in chunks of steps (CpuCheckPacer) and the thread's CPU clock is
  // read between them (a solver stopped by its per-call step limit resumes where it was).
  const long max_steps = options().max_steps;
  const double cpu_deadline = options().cpu_deadline_s;
  const bool cpu_budget = std::isfinite(cpu_deadline);
  const int too_much_work = family_ == Family::kCvode ? CV_TOO_MUCH_WORK : ARK_TOO_MUCH_WORK;
  int flag = 0;
  double t_reached = CurrentTime();
  bool evolved = false;  // y and t_reached hold the solver's state after a chunk
  bool cpu_spent = false;
  for (;;) {
    const long remaining = max_steps - NumSteps();
    const bool beyond = t_out > CurrentTime();  // steps are needed to reach t_out
    cpu_spent = cpu_budget && beyond && CpuDeadlinePassed();
    if ((remaining <= 0 && beyond) || cpu_spent) {
      // A budget is spent and t_out lies beyond the last internal step: stop at the last
      // output (or where the last chunk stopped).
      flag = too_much_work;
      if (!evolved) {
        t_reached = last_time();
        std::copy(last_state(), last_state() + state_size(), y);
      }
      break;
    }
    CpuCheckPacer& pacer = cpu_check_pacer();
    const long chunk = cpu_budget ? pacer.Chunk(remaining) : remaining;
    CheckSetup(SetMaxNumSteps(std::max(chunk, 1L)), "SetMaxNumSteps");
    const long steps_before = NumSteps();
    pacer.Start();
    // A failure before the first step leaves y and t_reached unwritten: poison them so the
    // base falls back to the last output.
    std::fill(y, y + state_size(), std::numeric_limits<double>::quiet_NaN());
    t_reached = std::numeric_limits<double>::quiet_NaN();
    flag = Evolve(t_out, out_.get(), &t_reached);
    pacer.Finish(NumSteps() - steps_before);
    if (flag >= 0) return {IntegratorStatus::kOk, t_out, {}};
    evolved = true;
    if (flag == too_much_work && chunk < remaining) continue;  // only the chunk ran out
    if (family_ == Family::kArkode && flag != ARK_TOO_MUCH_WORK) {
      // When a step fails ARKODE 6.4 returns the last step's state with the time of the
      // failed stage (tcur), not the step's: the pair is inconsistent. Use the last output.
      // (The step budget runs out between steps, where the pair is consistent.)
      t_reached = last_time();
      std::copy(last_state(), last_state() + state_size(), y);
    }
    break;
  }

  FailureContext context{family_,   flag,  name(),    implicit_, fixed_point_,
                         t_reached, t_out, max_steps, &rhs_,     errors_.message()};
  AdvanceResult result = FailureResult(context);
  if (cpu_spent) result.message = CpuBudgetMessage(name(), result.t, t_out);
  return result;
}

}  // namespace mbstream::sundials
