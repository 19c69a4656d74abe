// Maps a failed IDASolve return to an IntegratorStatus and a message that says what
// happened, at which time, and what to try.
#pragma once

#include <string>

#include "server/integrate/integrator.h"

namespace mbstream::sundials {

struct IdaFailureContext {
  int flag;                    // IDASolve's (negative) return flag
  double t_reached;            // s, the solver's last good time
  double t_out;                // s, the requested output time
  long max_steps;              // the step budget
  double last_step;            // s, the last step size tried
  double min_step;             // s, the smallest step allowed
  long error_test_failures;    // so far
  long convergence_failures;   // so far
  const char* residual_event;  // "" or what the residual adapter saw (non-finite values)
  const char* solver_message;  // IDA's own last error message ("" for none)
};

// The result of the failed call, with `t` = context.t_reached.
AdvanceResult IdaFailureResult(const IdaFailureContext& context);

}  // namespace mbstream::sundials
