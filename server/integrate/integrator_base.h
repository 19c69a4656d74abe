// What every integrator shares: the last good output, the health check of each returned
// state, the stop time and the sticky failure. Implementations supply DoAdvance.
#pragma once

#include <vector>

#include "server/integrate/chunked_solver.h"
#include "server/integrate/cpu_check_pacer.h"
#include "server/integrate/failure_messages.h"
#include "server/integrate/integrator.h"
#include "server/integrate/thread_cpu_clock.h"

namespace mbstream {

class IntegratorBase : public Integrator {
 public:
  IntegratorBase(const IntegratorBase&) = delete;
  IntegratorBase& operator=(const IntegratorBase&) = delete;

  AdvanceResult AdvanceTo(double t_out, double* y) final;
  bool Restart(double t0, const double* y0, const IntegratorOptions& options) final;

 protected:
  IntegratorBase(int size, double t0, const double* y0, const IntegratorOptions& options);

  // Advances from last_time() to t_out (last_time() < t_out <= t_final) and writes y(t_out)
  // into y. On failure returns status != kOk with `t` = the last good time and y the state
  // there; if that state is not healthy the base falls back to the last output.
  virtual AdvanceResult DoAdvance(double t_out, double* y) = 0;

  // Restart's part of the implementation, its checks passed (options: the new ones, not yet
  // options()): starts the method again at (t0, y0) without allocating. false when it cannot
  // (nothing changed then).
  virtual bool DoRestart(double /*t0*/, const double* /*y0*/,
                         const IntegratorOptions& /*options*/) {
    return false;
  }

  // Fixed-step, explicit or implicit: the advice on failures differs.
  virtual MethodKind method_kind() const = 0;

  int state_size() const { return size_; }
  double last_time() const { return last_t_; }
  const double* last_state() const { return last_y_.data(); }  // the last output, at last_time()
  const IntegratorOptions& options() const { return options_; }
  // Replaces the options (Retune): the CPU deadline with them.
  void ReplaceOptions(const IntegratorOptions& options);
  bool failed() const { return failed_; }
  // Whether the thread's CPU clock has passed options().cpu_deadline_s (cheap: CpuDeadline).
  bool CpuDeadlinePassed() { return cpu_deadline_.Passed(); }
  // Paces the checks of the CPU budget (how many steps between two).
  CpuCheckPacer& cpu_check_pacer() { return cpu_check_pacer_; }
  // Runs `solver` from last_time() towards t_out under options()' step budget (over the
  // whole run) and CPU deadline (chunked_solver.h). y is the solver's output: before each
  // call it is poisoned with NaN (a call that fails before its first step writes nothing, and
  // the base then falls back to the last output); stopped by a budget before any call, it
  // holds the last output.
  ChunkedSolve SolveInChunks(double t_out, double* y, ChunkedSolver& solver);

 private:
  int size_;
  IntegratorOptions options_;
  CpuDeadline cpu_deadline_;
  CpuCheckPacer cpu_check_pacer_;
  double last_t_;
  std::vector<double> last_y_;  // the last good output, at last_t_
  bool failed_ = false;
  AdvanceResult failure_;
};

}  // namespace mbstream
