// The messages of failed integrations: what happened, when, and what to try. Built only on
// the failure path (they allocate).
#pragma once

#include <string>

#include "server/integrate/integrator.h"
#include "server/integrate/rhs_adapter.h"
#include "shared/common/format.h"

namespace mbstream {

// What kind of method failed: the advice differs.
enum class MethodKind { kFixedStep, kExplicit, kImplicit };

// kDiverged: the state became non-finite or exceeded `limit` at t.
std::string DivergedMessage(const char* solver, double t, double limit, MethodKind kind);

// kTooMuchWork: the max_steps budget ran out at t_reached, before t_out.
std::string TooMuchWorkMessage(const char* solver, long max_steps, double t_reached, double t_out,
                               bool implicit);

// kTooMuchWork from the CPU budget: the thread's CPU clock passed the deadline at t_reached,
// before t_out.
std::string CpuBudgetMessage(const char* solver, double t_reached, double t_out);

// The failure that the right-hand side adapter recorded (rhs.event() != kNone), as a
// result at the last good time t_good: kDiverged or kRhsFailure.
AdvanceResult RhsEventResult(const char* solver, const RhsAdapter& rhs, double t_good,
                             MethodKind kind);

}  // namespace mbstream
