// An ODE whose solution must stay on a manifold (the constraints of a closed kinematic loop)
// says how to get back onto it. An OdeSystem that also derives from ManifoldProjection is
// projected after each accepted step by CVODE BDF (CVodeSetProjFn); the other methods
// ignore it, and the system's own stabilisation (Baumgarte) must then hold the drift.
#pragma once

namespace mbstream {

class ManifoldProjection {
 public:
  virtual ~ManifoldProjection() = default;

  // Writes `correction` (the OdeSystem's size() doubles) such that y + correction lies on
  // the manifold at time t. Returns 0, > 0 for a recoverable failure (the step is retried
  // smaller), < 0 for an unrecoverable one. Must not allocate.
  virtual int Project(double t, const double* y, double* correction) = 0;
};

}  // namespace mbstream
