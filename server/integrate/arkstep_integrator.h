// ARKODE's ARKStep with one part of its additive splitting only: adaptive explicit
// Runge-Kutta (ERK, the right-hand side as the explicit part) or diagonally implicit
// Runge-Kutta (DIRK, as the implicit part, Newton iteration with a dense linear solver),
// with a named Butcher table.
//
// ERK goes through ARKStep rather than ERKStep: in SUNDIALS 6.4 ERKStep integrates the
// Verner 8-5-6 table with third-order accuracy only, while ARKStep attains its sixth order.
// Outputs between internal steps come from ARKODE's Hermite interpolant (degree <= 5), so
// for the high-order tables (verner, fehlberg) with long steps the outputs are less accurate
// than the internal steps; set a max_step near the output interval if that matters.
#pragma once

#include <string>

#include "server/integrate/butcher_tables.h"
#include "server/integrate/sundials_integrator.h"

namespace mbstream::sundials {

class ArkStepIntegrator final : public SundialsIntegrator {
 public:
  enum class Variant {
    kErk,   // explicit table, see FindErkTable
    kDirk,  // diagonally implicit table, see FindDirkTable
  };

  // options.erk_table names the table; throws InputError if unknown.
  ArkStepIntegrator(Variant variant, OdeSystem& system, double t0, const double* y0,
                    const IntegratorOptions& options);

  SolverStats stats() const override;
  const char* name() const override { return name_.c_str(); }

 private:
  long NumSteps() const override;
  double CurrentTime() const override;
  int SetMaxNumSteps(long steps) override;
  int Evolve(double t_out, N_Vector y, double* t_reached) override;
  int SetStopTime(double t_final) override;
  int ReInit(double t0) override;

  Variant variant_;
  long roots_found_ = 0;  // root returns of Evolve
  const ButcherTableInfo& table_;
  std::string name_;
  // Destroyed in reverse order: the solver memory before the solvers it uses.
  Matrix matrix_;
  LinearSolver linear_solver_;
  SolverMemory memory_;
};

}  // namespace mbstream::sundials
