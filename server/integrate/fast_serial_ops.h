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

// A SUNDenseMatrix: zero, copy, scale-add-identity; clones inherit the replacements.
void InstallFastDenseMatrixOps(SUNMatrix matrix);

// A SUNLinSol_Dense: LU factorisation (setup; structured when the matrix allows) and solve.
void InstallFastDenseSolverOps(SUNLinearSolver solver);

}  // namespace mbstream::sundials
