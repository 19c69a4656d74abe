// Block elimination for the Newton matrix of a first-order form of a second-order ODE.
//
// For y = [q; qd] with q' = qd, the Jacobian is J = [0 I; A B], and CVODE's Newton matrix
// M = I - gamma J is [I, c I; M21, M22] with c = -gamma. Eliminating the top block (M11 = I,
// no pivoting needed) leaves the Schur complement S = M22 - M21 M12 = M22 - c M21 of half the
// size: factoring it costs an eighth of the full LU, and a solve is x2 = S^-1 (b2 - M21 b1),
// x1 = b1 - c x2. Partial pivoting inside S keeps this a stable factorisation of M.
//
// Appended quadratures (appended_quadratures.h) add r trailing states that feed nothing back
// and whose Jacobian rows are zero: M = [[I, c I; M21, M22], 0; 0, I_r]. Their rows and
// columns are recognised as exact identity rows and columns at the end, and their part of a
// solve is x3 = b3; the leading 2m x 2m block is factored and solved as without them, bit
// for bit.
//
// The structure is detected from the matrix entries (compared exactly, at every setup); a
// matrix without it is left for the full LU. The factors live in the matrix itself (S's LU
// in the M22 block; M21 and the top half untouched) and in the dense solver's pivot array
// (n entries), so nothing is allocated. Specialised at compile time for 2m = 12.
#pragma once

#include <sundials/sundials_types.h>

namespace mbstream::sundials {

// Returned by FactorStructured for a matrix without the structure (left untouched).
inline constexpr sunindextype kNotStructured = -1;

// If the column-major n x n matrix `a` is [[I, c I; M21, M22], 0; 0, I_r] (r >= 0 trailing
// identity rows and columns, 2m = n - r >= 2, the top half checked entry by entry, c one
// scalar), overwrites M22 with the LU factors of S = M22 - c M21, writes S's row
// interchanges to pivots[0, m) and marks pivots[n - 1] as holding this factorisation of
// half size m. Returns 0, the 1-based column of `a` of a zero pivot of S (the matrix is
// singular), or kNotStructured.
sunindextype FactorStructured(sunindextype n, double* a, sunindextype* pivots);

// pivots[n - 1] after FactorStructured: -(m + 1), negative; a full LU records a row index
// there (n - 1), never negative.
inline constexpr sunindextype StructuredMark(sunindextype m) { return -(m + 1); }

// Whether `pivots` (of an n x n matrix) hold a factorisation by FactorStructured rather than
// a full LU.
inline bool IsStructuredFactor(sunindextype n, const sunindextype* pivots) {
  return n >= 2 && pivots[n - 1] < 0;
}

// Solves M x = b with the factors from a successful FactorStructured; x may be b.
void SolveStructured(sunindextype n, const double* a, const sunindextype* pivots, const double* b,
                     double* x);

}  // namespace mbstream::sundials
