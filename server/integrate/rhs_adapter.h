// Calls an OdeSystem's right-hand side for an integrator: counts the calls, refuses
// diverged states and non-finite derivatives (as unrecoverable failures, so that the run
// stops at once) and remembers the first such event for the failure message. After an
// unrecoverable failure every later call fails too. An exception from the system is caught
// here (it must not cross SUNDIALS' C frames) and becomes such a failure, its message kept.
#pragma once

#include "server/integrate/ode_system.h"

namespace mbstream {

class RhsAdapter {
 public:
  // What made an evaluation fail unrecoverably (the first such event is kept).
  enum class Event {
    kNone,
    kDiverged,             // y non-finite or beyond the divergence limit
    kNonFiniteDerivative,  // y healthy but f(t, y) non-finite
    kFailed,               // OdeSystem::Rhs returned < 0
    kThrew,                // OdeSystem::Rhs or Jacobian threw (what() in event_what())
  };

  // The divergence limit applies to the first `limited_states` states of y (0 = all; the
  // rest, appended quadratures, need only be finite).
  RhsAdapter(OdeSystem& system, double divergence_limit, int limited_states = 0);
  RhsAdapter(const RhsAdapter&) = delete;
  RhsAdapter& operator=(const RhsAdapter&) = delete;

  // ydot = f(t, y), with the checks above. Returns 0, > 0 (the system's recoverable
  // failure) or < 0 (unrecoverable, an exception included). Allocates nothing.
  int Evaluate(double t, const double* y, double* ydot) noexcept;

  // The system's own Jacobian (column-major); returns its code (< 0 when it threw).
  // Allocates nothing.
  int EvaluateJacobian(double t, const double* y, const double* fy, double* jac_col_major) noexcept;

  // Records an exception `what` at time t as the unrecoverable event kThrew (the first event
  // is kept) and returns the code for SUNDIALS (< 0). For the C callbacks' boundary.
  int RecordException(double t, const char* what) noexcept;

  // As made: no calls counted, no event (Integrator::Restart).
  void Reset() noexcept;

  OdeSystem& system() const { return system_; }
  int size() const { return size_; }
  double divergence_limit() const { return divergence_limit_; }
  long num_evals() const { return num_evals_; }

  Event event() const { return event_; }
  double event_time() const { return event_time_; }       // s, when `event` happened
  int event_code() const { return event_code_; }          // the system's code for kFailed
  const char* event_what() const { return event_what_; }  // kThrew: the exception's message
  // The last recoverable failure (code > 0) and its time; 0 when there was none.
  int last_recoverable_code() const { return last_recoverable_code_; }
  double last_recoverable_time() const { return last_recoverable_time_; }

 private:
  int Fail(Event event, double t, int code) noexcept;

  OdeSystem& system_;
  int size_;
  int limited_states_;  // the states under the divergence limit
  double divergence_limit_;
  long num_evals_ = 0;
  Event event_ = Event::kNone;
  double event_time_ = 0.0;
  int event_code_ = 0;
  char event_what_[256] = {};
  int last_recoverable_code_ = 0;
  double last_recoverable_time_ = 0.0;
};

}  // namespace mbstream
