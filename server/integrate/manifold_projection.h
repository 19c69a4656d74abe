// An ODE whose solution must stay on a manifold (the constraints of a closed kinematic loop,
// unit quaternions) says how to get back onto it. An OdeSystem that also derives from
// ManifoldProjection, with Projects() true, is projected after each accepted step by CVODE BDF
// (CVodeSetProjFn); the other methods ignore it, and the system's own stabilisation
// (Baumgarte) must then hold the drift, unless ProjectsEveryMethod(): then the fixed-step
// methods (RK4, semi-implicit Euler) and ARKODE (its post-step hook) project too, in place,
// after each step. CVODE Adams never projects (a multistep method's history would not match
// a changed state): its drift stays of the order of the tolerances.
#pragma once

namespace mbstream {

class OdeSystem;

class ManifoldProjection {
 public:
  virtual ~ManifoldProjection() = default;

  // Writes `correction` (the OdeSystem's size() doubles) such that y + correction lies on
  // the manifold at time t. Returns 0, > 0 for a recoverable failure (the step is retried
  // smaller), < 0 for an unrecoverable one. Must not allocate.
  virtual int Project(double t, const double* y, double* correction) = 0;

  // Whether there is anything to project (a system may derive from this for only some of its
  // models); false: no method projects.
  virtual bool Projects() const { return true; }

  // Whether the projection is exact and cheap enough (normalising quaternions) for every
  // one-step method to apply after each step, through ProjectInPlace.
  virtual bool ProjectsEveryMethod() const { return false; }

  // For ProjectsEveryMethod(): puts y (size() doubles) back on the manifold, in place. Returns
  // 0, or an unrecoverable code < 0. Must not allocate.
  virtual int ProjectInPlace(double /*t*/, double* /*y*/) { return -1; }
};

// `system` as a ManifoldProjection that projects (Projects()), else null.
ManifoldProjection* ProjectionOf(OdeSystem& system);

// The same, when it also ProjectsEveryMethod(), else null.
ManifoldProjection* EveryStepProjectionOf(OdeSystem& system);

}  // namespace mbstream
