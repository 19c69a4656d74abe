// Maps a failed CVode / ARKStepEvolve return to an IntegratorStatus and a
// message that says what happened, at which time, and what to try.
#pragma once

#include "server/integrate/integrator.h"
#include "server/integrate/rhs_adapter.h"
#include "server/integrate/sundials_handles.h"

namespace mbstream::sundials {

struct FailureContext {
  Family family;
  int flag;                    // the solver's (negative) return flag
  const char* solver;          // Integrator::name()
  bool implicit;               // BDF/DIRK (Newton) rather than Adams/ERK
  bool fixed_point;            // Adams with fixed-point iteration
  double t_reached;            // s, the solver's last good time
  double t_out;                // s, the requested output time
  long max_steps;              // the step budget
  const RhsAdapter* rhs;       // its recorded event, if any, takes precedence
  const char* solver_message;  // SUNDIALS' own last error message ("" for none)
};

// The result of the failed call, with `t` = context.t_reached.
AdvanceResult FailureResult(const FailureContext& context);

}  // namespace mbstream::sundials
