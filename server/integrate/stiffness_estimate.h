// An estimate of an ODE's stiffness at one state: the largest eigenvalue magnitude of its
// Jacobian df/dy, for the message of a run whose budget ran out. Failure path only: it
// allocates.
#pragma once

#include "server/integrate/ode_system.h"

namespace mbstream {

// max |lambda| of df/dy at (t, y), 1/s: from the system's own Jacobian when it has one, else
// from forward differences of Rhs. Returns -1 when it cannot be estimated (a failing or
// non-finite right-hand side, a system too large to decompose densely).
double LargestEigenvalueEstimate(OdeSystem& system, double t, const double* y);

}  // namespace mbstream
