#include "server/integrate/rhs_adapter.h"

#include <cstdio>

#include "server/integrate/c_boundary.h"
#include "server/integrate/state_health.h"

namespace mbstream {

RhsAdapter::RhsAdapter(OdeSystem& system, double divergence_limit, int limited_states)
    : system_(system),
      size_(system.size()),
      limited_states_(LimitedStates(system.size(), limited_states)),
      divergence_limit_(divergence_limit) {}

void RhsAdapter::Reset() noexcept {
  num_evals_ = 0;
  event_ = Event::kNone;
  event_time_ = 0.0;
  event_code_ = 0;
  event_what_[0] = '\0';
  last_recoverable_code_ = 0;
  last_recoverable_time_ = 0.0;
}

int RhsAdapter::Fail(Event event, double t, int code) noexcept {
  if (event_ == Event::kNone) {
    event_ = event;
    event_time_ = t;
    event_code_ = code;
  }
  return code < 0 ? code : -1;
}

int RhsAdapter::RecordException(double t, const char* what) noexcept {
  if (event_ == Event::kNone) std::snprintf(event_what_, sizeof(event_what_), "%s", what);
  return Fail(Event::kThrew, t, -1);
}

int RhsAdapter::Evaluate(double t, const double* y, double* ydot) noexcept {
  ++num_evals_;
  // The run is over after an unrecoverable failure. Keep failing, so that a solver that
  // retries anyway (CVODE's fixed-point iteration treats every failure as recoverable)
  // stops at once instead of creeping towards the failure time with ever smaller steps.
  if (event_ != Event::kNone) return -1;
  if (!IsHealthyState(y, size_, limited_states_, divergence_limit_)) {
    return Fail(Event::kDiverged, t, -1);
  }
  const int code =
      sundials::AtCBoundary([&] { return system_.Rhs(t, y, ydot); },
                            [&](const char* what) { return RecordException(t, what); });
  if (event_ == Event::kThrew) return code;
  if (code < 0) return Fail(Event::kFailed, t, code);
  if (code > 0) {
    last_recoverable_code_ = code;
    last_recoverable_time_ = t;
    return code;
  }
  if (!IsFiniteState(ydot, size_)) return Fail(Event::kNonFiniteDerivative, t, -1);
  return 0;
}

int RhsAdapter::EvaluateJacobian(double t, const double* y, const double* fy,
                                 double* jac_col_major) noexcept {
  return sundials::AtCBoundary([&] { return system_.Jacobian(t, y, fy, jac_col_major); },
                               [&](const char* what) { return RecordException(t, what); });
}

}  // namespace mbstream
