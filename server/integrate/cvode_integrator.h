// CVODE: variable-order BDF with Newton iteration and a dense linear solver (stiff
// problems), or Adams-Moulton with fixed-point iteration (non-stiff problems).
#pragma once

#include "server/integrate/sundials_integrator.h"

namespace mbstream::sundials {

class CvodeIntegrator final : public SundialsIntegrator {
 public:
  enum class Variant {
    kBdf,    // BDF orders 1-5, Newton + SUNLinSol_Dense, the system's Jacobian if it has one
    kAdams,  // Adams-Moulton orders 1-12, SUNNonlinSol_FixedPoint (no Jacobian)
  };

  CvodeIntegrator(Variant variant, OdeSystem& system, double t0, const double* y0,
                  const IntegratorOptions& options);

  SolverStats stats() const override;
  const char* name() const override;

 private:
  long NumSteps() const override;
  double CurrentTime() const override;
  int SetMaxNumSteps(long steps) override;
  int Evolve(double t_out, N_Vector y, double* t_reached) override;
  int SetStopTime(double t_final) override;
  int ReInit(double t0) override;

  Variant variant_;
  long roots_found_ = 0;  // root returns of Evolve
  // Destroyed in reverse order: the solver memory before the solvers it uses.
  Matrix matrix_;
  LinearSolver linear_solver_;
  NonlinearSolver nonlinear_solver_;
  SolverMemory memory_;
};

}  // namespace mbstream::sundials
