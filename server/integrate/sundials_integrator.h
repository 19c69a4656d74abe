// What the SUNDIALS integrators (CVODE, ARKODE's ARKStep) share: the context, the
// state vectors, the callbacks' data, the step budget and the failure mapping.
#pragma once

#include "server/integrate/integrator_base.h"
#include "server/integrate/rhs_adapter.h"
#include "server/integrate/sundials_callbacks.h"
#include "server/integrate/sundials_failure.h"
#include "server/integrate/sundials_handles.h"

namespace mbstream::sundials {

class SundialsIntegrator : public IntegratorBase, protected ChunkedSolver {
 public:
  bool Retune(const IntegratorOptions& options) final;

 protected:
  SundialsIntegrator(OdeSystem& system, double t0, const double* y0,
                     const IntegratorOptions& options, Family family, bool implicit,
                     bool fixed_point);

  // The solver calls DoAdvance needs besides ChunkedSolver's NumSteps and CurrentTime.
  virtual int SetMaxNumSteps(long steps) = 0;  // per call of Evolve
  // CVode / ARKStepEvolve in normal mode (interpolating at t_out).
  virtual int Evolve(double t_out, N_Vector y, double* t_reached) = 0;
  // The stop time, for Retune. (The tolerances need no call: the error weights come from
  // ErrorWeightCallback, which reads them from callback_data(). CVODE and ARKODE hand their
  // weight function its data only in their initial set-up: *SStolerances after the first
  // step would leave it without.)
  virtual int SetStopTime(double t_final) = 0;
  // CVodeReInit / ARKStepReInit at (t0, initial_state()), the root count reset (Restart).
  virtual int ReInit(double t0) = 0;

  // Throws InternalError naming `call` and SUNDIALS' message when flag < 0 (set-up only).
  void CheckSetup(int flag, const char* call) const;
  // Throws InternalError when a constructor returned null.
  void CheckCreated(const void* object, const char* call) const;

  SUNContext context() const { return context_.get(); }
  N_Vector initial_state() const { return y0_.get(); }
  const RhsAdapter& rhs() const { return rhs_; }
  ErrorSink& errors() { return errors_; }
  // The callbacks' user_data; its `solver` is set by the derived class once created.
  CallbackData& callback_data() { return callback_data_; }

 private:
  AdvanceResult DoAdvance(double t_out, double* y) final;
  bool DoRestart(double t0, const double* y0, const IntegratorOptions& options) final;
  void LimitSteps(long steps) final { CheckSetup(SetMaxNumSteps(steps), "SetMaxNumSteps"); }
  int Solve(double t_out, double* t_reached) final { return Evolve(t_out, out_.get(), t_reached); }
  int TooMuchWorkFlag() const final;
  MethodKind method_kind() const final {
    return implicit_ ? MethodKind::kImplicit : MethodKind::kExplicit;
  }

  RhsAdapter rhs_;
  CallbackData callback_data_;
  ErrorSink errors_;
  Family family_;
  bool implicit_;
  bool fixed_point_;
  Context context_;
  Vector y0_;   // the initial state (owned data)
  Vector out_;  // wraps the caller's output buffer (no data of its own)
};

}  // namespace mbstream::sundials
