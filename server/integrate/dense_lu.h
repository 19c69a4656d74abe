// LU factorisation with partial pivoting and the matching solve, for a column-major square
// block of a larger matrix: SUNDIALS' denseGETRF / denseGETRS, column by column, with a
// leading dimension. Shared by the dense linear solver (the whole matrix) and the structured
// one (the Schur complement, stored in place in the bottom-right block).
//
// Sizes and leading dimensions are either sunindextype or Fixed<k>: a compile-time constant,
// with which the loops unroll (CVODE calls these about once per step on a 12-state ODE).
#pragma once

#include <cmath>
#include <type_traits>
#include <utility>

#include <sundials/sundials_types.h>

namespace mbstream::sundials {

template <sunindextype k>
using Fixed = std::integral_constant<sunindextype, k>;

// Factors the n x n block `a` (leading dimension ld) in place as P a = L U, L unit lower
// triangular; pivots[k] is the row swapped with row k at step k (whole rows of the block).
// Returns 0, or the 1-based column of the first zero pivot (the factorisation stops there).
template <typename Size, typename Stride>
sunindextype LuFactor(Size n, Stride ld, double* a, sunindextype* pivots) {
  for (sunindextype k = 0; k < n; ++k) {
    double* col_k = a + k * ld;
    sunindextype l = k;
    for (sunindextype i = k + 1; i < n; ++i) {
      if (std::abs(col_k[i]) > std::abs(col_k[l])) l = i;
    }
    pivots[k] = l;
    if (col_k[l] == 0.0) return k + 1;
    if (l != k) {
      for (sunindextype j = 0; j < n; ++j) std::swap(a[j * ld + l], a[j * ld + k]);
    }
    const double mult = 1.0 / col_k[k];
    for (sunindextype i = k + 1; i < n; ++i) col_k[i] *= mult;
    for (sunindextype j = k + 1; j < n; ++j) {
      double* col_j = a + j * ld;
      const double a_kj = col_j[k];
      if (a_kj != 0.0) {
        for (sunindextype i = k + 1; i < n; ++i) col_j[i] -= a_kj * col_k[i];
      }
    }
  }
  return 0;
}

// Overwrites x with the solution of (P^T L U) x = x, the factors from LuFactor.
template <typename Size, typename Stride>
void LuSubstitute(Size n, Stride ld, const double* a, const sunindextype* pivots, double* x) {
  for (sunindextype k = 0; k < n; ++k) {
    if (pivots[k] != k) std::swap(x[k], x[pivots[k]]);
  }
  for (sunindextype k = 0; k < n - 1; ++k) {
    const double* col_k = a + k * ld;
    const double xk = x[k];
    for (sunindextype i = k + 1; i < n; ++i) x[i] -= col_k[i] * xk;
  }
  for (sunindextype k = n - 1; k > 0; --k) {
    const double* col_k = a + k * ld;
    x[k] /= col_k[k];
    const double xk = x[k];
    for (sunindextype i = 0; i < k; ++i) x[i] -= col_k[i] * xk;
  }
  x[0] /= a[0];
}

}  // namespace mbstream::sundials
