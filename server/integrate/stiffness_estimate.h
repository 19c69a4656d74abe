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

// Both ends of df/dy's spectrum at (t, y): the largest eigenvalue magnitude (stiffness) and the
// largest real part (> 0: nearby solutions separate at that local rate, 1/s). Both -1 / 0
// when it cannot be estimated (`ok` false).
struct JacobianSpectrum {
  bool ok = false;
  double largest_magnitude = -1.0;  // 1/s
  double largest_real = 0.0;        // 1/s
};
JacobianSpectrum EstimateJacobianSpectrum(OdeSystem& system, double t, const double* y);

}  // namespace mbstream
