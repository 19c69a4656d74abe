// An ordinary differential equation y' = f(t, y), as the integrators see it: no mechanics.
#pragma once

namespace mbstream {

class OdeSystem {
 public:
  virtual ~OdeSystem() = default;

  // Number of states (the length of y).
  virtual int size() const = 0;

  // ydot = f(t, y). Returns 0 on success, > 0 for a recoverable failure (the solver retries
  // with a smaller step), < 0 for an unrecoverable one (the run stops). Called on the hot
  // path: must not allocate.
  virtual int Rhs(double t, const double* y, double* ydot) = 0;

  // Optional own dense Jacobian df/dy, column-major, size x size; fy = f(t, y). Return
  // false from HasJacobian to let the integrator use finite differences (SUNDIALS' difference
  // quotients: size() evaluations of Rhs). Jacobian returns 0 on success, > 0 recoverable,
  // < 0 unrecoverable. Called on the hot path: must not allocate.
  virtual bool HasJacobian() const { return false; }
  virtual int Jacobian(double /*t*/, const double* /*y*/, const double* /*fy*/,
                       double* /*jac_col_major*/) {
    return -1;
  }

  // For the semi-implicit Euler method: the number of leading "position" states whose
  // derivative is the following block of "velocity" states (y = [x; v; rest], x' = v).
  // 0 = not second order (the method is then refused with a clear error).
  virtual int num_positions() const { return 0; }

  // With num_positions() > 0: the number of velocity states v after the positions x, and the
  // positions' rate x' for (x, v). The defaults are x' = v (as many velocities as positions);
  // a system whose positions are not its velocities' integrals (quaternions) overrides both.
  // PositionRate must not allocate.
  virtual int num_velocities() const { return num_positions(); }
  virtual void PositionRate(const double* /*x*/, const double* v, double* x_rate) {
    for (int i = 0; i < num_positions(); ++i) x_rate[i] = v[i];
  }

  // Optional quadratures: integrals Q(t) = int g(s, y(s)) ds from t0 (Q(t0) = 0) whose
  // integrand g does not feed back into f (the work of drives and damping, say). The
  // integrators append them to the state with a zero error weight, so they never shorten a
  // step (appended_quadratures.h). Quadrature writes g(t, y) into qdot (num_quadratures()
  // doubles); codes as Rhs. Must not allocate.
  virtual int num_quadratures() const { return 0; }
  virtual int Quadrature(double /*t*/, const double* /*y*/, double* /*qdot*/) { return -1; }

  // Optional root functions g(t, y), num_roots() of them: CVODE and ARKODE end a step where
  // one changes sign and go on from there (the fixed-step methods ignore them), so that no
  // step steps over the event (a contact beginning or ending). Roots writes g (num_roots()
  // doubles); codes as Rhs. Must not allocate. The integrators move each g to at least
  // kRootFloor from 0 (sundials_callbacks.h says why).
  virtual int num_roots() const { return 0; }
  virtual int Roots(double /*t*/, const double* /*y*/, double* /*g*/) { return -1; }

  // f and g at the same (t, y), as the appended quadratures ask for them on every
  // right-hand side: a system whose g needs what f computes (the joint-space ODE's drive
  // efforts need its accelerations) overrides this to evaluate once. The result must equal
  // Rhs followed by Quadrature bit for bit; codes as Rhs. Must not allocate.
  virtual int RhsAndQuadrature(double t, const double* y, double* ydot, double* qdot) {
    if (const int code = Rhs(t, y, ydot); code != 0) return code;
    return Quadrature(t, y, qdot);
  }
};

}  // namespace mbstream
