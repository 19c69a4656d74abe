// Quadratures as appended states (CVODE has no quadratures, only CVODES has): the system
// y' = f(t, y) with quadratures Q' = g(t, y) becomes z = [y; Q], z' = [f; g], advanced by the
// run's method; the appended states get a zero error weight (IntegratorOptions::error_states),
// so they never shorten a step. (The weighted RMS norm still divides by the full length, so
// the tolerances act a few per cent looser than on y alone; y itself is not bit for bit that
// of a run without quadratures, which is why a run asks for them only when it needs them.)
#pragma once

#include <memory>
#include <vector>

#include "server/integrate/integrator.h"

namespace mbstream {

// [y; Q] as one ODE. Its Jacobian, when the system has one, is the system's with zero rows
// and columns for Q (Q feeds nothing back; a zero row only lags Q's Newton update by one
// iteration inside DIRK's stage solves). Keeps a reference to `system`.
class AppendedQuadratureOde : public OdeSystem {
 public:
  explicit AppendedQuadratureOde(OdeSystem& system);

  int size() const override { return n_ + nq_; }
  int Rhs(double t, const double* z, double* zdot) override;
  bool HasJacobian() const override { return system_.HasJacobian(); }
  int Jacobian(double t, const double* z, const double* fz, double* jac_col_major) override;
  int num_positions() const override { return system_.num_positions(); }

 private:
  OdeSystem& system_;
  const int n_, nq_;
  std::vector<double> jacobian_;  // n x n workspace for the system's own Jacobian
};

// Integrates `system` and its quadratures as AppendedQuadratureOde with the method of
// `options`; AdvanceTo writes y only, Quadratures the appended states.
std::unique_ptr<Integrator> MakeAppendedQuadratureIntegrator(OdeSystem& system, double t0,
                                                             const double* y0,
                                                             const IntegratorOptions& options);

}  // namespace mbstream
