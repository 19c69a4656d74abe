// Optimised replacements for the hot operations of SUNDIALS' serial vector, dense matrix and
// dense linear solver, installed into the objects' operation tables.
//
// Debian's SUNDIALS 6.4 packages are built without optimisation (every function spills its
// arguments to the stack; a 12 x 12 LU back-substitution costs 4,000 instructions), and for
// small systems CVODE spends most of its time in these kernels: vector linear sums (its
// predictor and corrector loops), weighted norms, matrix copies and the LU. The replacements
// compute the same quantities with the same algorithms (the LU is SUNDIALS' own partial
// pivoting, column by column), compiled with the project's flags; they also supply the fused
// vector operations (linear combination, scale-add-multi), which CVODE otherwise emulates
// with one linear sum per term. The vector results are those of the plain formulas, bit for
// bit (a x + b y, ...; the fast paths only skip multiplications by 1, which are exact). The
// one change of algorithm: the Newton matrix of a second-order ODE, y = [q; qd], is factored
// through its half-size Schur complement (structured_dense_solver.h). Nothing here allocates.
#pragma once

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

namespace mbstream::sundials {

// A serial N_Vector (N_VNew_Serial / N_VMake_Serial): replaces the arithmetic and norm
// operations and enables the fused ones. Vectors cloned from it (CVODE's and ARKODE's
// internal vectors are clones of the initial state) inherit the table.
void InstallFastSerialOps(N_Vector vector);

// The states under error control of a weight vector of length n: all but its trailing
// zero weights, the appended quadratures' (appended_quadratures.h; a state under error
// control always has a positive weight, sundials_callbacks.h).
inline sunindextype ErrorControlledLength(sunindextype n, const double* weights) {
  while (n > 0 && weights[n - 1] == 0.0) --n;
  return n;
}

// The weighted RMS norm over the states under error control, sqrt(sum_i (x_i w_i)^2 / m) for
// the first m = ErrorControlledLength states: a system with appended quadratures has the
// norms, and so the steps, of the system alone, bit for bit (SUNDIALS' serial norm divides
// by the whole length). InstallFastSerialOps installs it; ARKODE's vectors, which keep
// SUNDIALS' other operations, get it alone from InstallErrorNorm.
double ErrorNorm(N_Vector x, N_Vector w);
void InstallErrorNorm(N_Vector vector);

// A SUNDenseMatrix: zero, copy, scale-add-identity; clones inherit the replacements.
void InstallFastDenseMatrixOps(SUNMatrix matrix);

// A SUNLinSol_Dense: LU factorisation (setup; structured when the matrix allows) and solve.
void InstallFastDenseSolverOps(SUNLinearSolver solver);

}  // namespace mbstream::sundials
