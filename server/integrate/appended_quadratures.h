// Quadratures as appended states (CVODE has no quadratures, only CVODES has): the system
// y' = f(t, y) with quadratures Q' = g(t, y) becomes z = [y; Q], z' = [f; g], advanced by the
// run's method. The appended states take no part in the error control: a zero error weight
// (IntegratorOptions::error_states), an error norm over y alone (ErrorNorm,
// fast_serial_ops.h), zero Jacobian rows and columns (also in the finite differences) and a
// Newton matrix whose leading block is y's own (structured_dense_solver.h). So y takes the
// steps, and has the values, of a run without quadratures, bit for bit, with every method:
// the adaptive ones (their norms and Newton matrices), RK4 and semi-implicit Euler (Q is
// advanced alongside y and never read). Q is the method's own quadrature of g: with the
// implicit methods its Newton update lags y's by one iteration (its Jacobian row is zero).
#pragma once

#include <memory>
#include <vector>

#include "server/integrate/integrator.h"
#include "server/integrate/manifold_projection.h"

namespace mbstream {

// [y; Q] as one ODE. Its Jacobian, when the system has one, is the system's with zero rows
// and columns for Q (Q feeds nothing back; a zero row only lags Q's Newton update by one
// iteration inside DIRK's stage solves). Keeps a reference to `system`.
//
// It passes on the system's own position rate (OdeSystem::PositionRate) and its projection,
// Q untouched: with every method when the system projects with every method
// (ManifoldProjection::ProjectsEveryMethod: unit quaternions), else with CVODE BDF only (the
// closed loops' constraints).
class AppendedQuadratureOde : public OdeSystem, public ManifoldProjection {
 public:
  explicit AppendedQuadratureOde(OdeSystem& system);

  int size() const override { return n_ + nq_; }
  int Rhs(double t, const double* z, double* zdot) override;
  bool HasJacobian() const override { return system_.HasJacobian(); }
  int Jacobian(double t, const double* z, const double* fz, double* jac_col_major) override;
  int num_positions() const override { return system_.num_positions(); }
  int num_velocities() const override { return system_.num_velocities(); }
  void PositionRate(const double* x, const double* v, double* x_rate) override {
    system_.PositionRate(x, v, x_rate);
  }

  // The system's root functions, of its own states (the leading n of z).
  int num_roots() const override { return system_.num_roots(); }
  int Roots(double t, const double* z, double* g) override { return system_.Roots(t, z, g); }
  bool Projects() const override { return projection_ != nullptr; }
  bool ProjectsEveryMethod() const override {
    return projection_ != nullptr && projection_->ProjectsEveryMethod();
  }
  int Project(double t, const double* z, double* correction) override;
  int ProjectInPlace(double t, double* z) override { return projection_->ProjectInPlace(t, z); }

 private:
  OdeSystem& system_;
  ManifoldProjection* const projection_;  // ProjectionOf(system_)
  const int n_, nq_;
  std::vector<double> jacobian_;  // n x n workspace for the system's own Jacobian
};

// Integrates `system` and its quadratures as AppendedQuadratureOde with the method of
// `options`; AdvanceTo writes y only, Quadratures the appended states.
std::unique_ptr<Integrator> MakeAppendedQuadratureIntegrator(OdeSystem& system, double t0,
                                                             const double* y0,
                                                             const IntegratorOptions& options);

}  // namespace mbstream
