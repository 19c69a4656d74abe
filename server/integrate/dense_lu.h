// LU factorisation with partial pivoting and the matching solve, for a column-major square
// block of a larger matrix: SUNDIALS' denseGETRF / denseGETRS, column by column, with a
// leading dimension. Shared by the dense linear solver (the whole matrix) and the structured
// one (the Schur complement, stored in place in the bottom-right block).
//
// Sizes and leading dimensions are either sunindextype or Fixed<k>: a compile-time constant,
// with which the loops unroll (CVODE calls these about once per step on a 12-state ODE).
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>

#include <sundials/sundials_types.h>

#include "server/integrate/double_pair.h"

namespace mbstream::sundials {

template <sunindextype k>
using Fixed = std::integral_constant<sunindextype, k>;

// Step k of the LU of LuFactor on columns [k, j_end) only: pivot search in column k, the
// swap of rows k and pivots[k] across all n columns, the multipliers, and the update of
// columns (k, j_end). Returns 0 or the 1-based column of a zero pivot.
template <typename Size, typename Stride>
sunindextype LuStep(Size n, Stride ld, double* a, sunindextype* pivots, sunindextype k,
                    sunindextype j_end) {
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
  for (sunindextype j = k + 1; j < j_end; ++j) {
    double* col_j = a + j * ld;
    const double a_kj = col_j[k];
    if (a_kj != 0.0) {
      for (sunindextype i = k + 1; i < n; ++i) col_j[i] -= a_kj * col_k[i];
    }
  }
  return 0;
}

// LuFactor for a large block (n >= kLuBlockMin), by panels of kLuPanel columns: each panel
// is factored by LuSteps, then every column to its right receives the panel's updates while
// it is in cache, all of an entry's updates in a register. Every entry sees the same
// operations in the same order as in the column-by-column LU (updates in step order, the
// same skipped zero multipliers), so the factors are the same bit for bit; only the memory
// traffic differs (the whole trailing block was read and written once per step).
inline constexpr sunindextype kLuBlockMin = 24;
inline constexpr int kLuPanel = 8;

namespace internal {

// The panel's rows (k0, k_end) of column col_j (U's entries), step by step as LuStep would.
inline void UpdatePanelRows(sunindextype ld, const double* a, sunindextype k0, sunindextype k_end,
                            double* col_j) {
  for (sunindextype k = k0; k + 1 < k_end; ++k) {
    const double a_kj = col_j[k];
    if (a_kj == 0.0) continue;
    const double* col_k = a + k * ld;
    for (sunindextype i = k + 1; i < k_end; ++i) col_j[i] -= a_kj * col_k[i];
  }
}

inline bool NoZeroIn(const double* u) {
  bool all = true;
  for (int s = 0; s < kLuPanel; ++s) all &= u[s] != 0.0;
  return all;
}

// The rows [k_end, n) of column col_j: each entry minus u_kj l_ik for the panel's steps k
// in order (skipping zero u_kj, as LuStep does).
inline void UpdateBelowPanel(sunindextype n, sunindextype ld, const double* a, sunindextype k0,
                             sunindextype k_end, double* col_j) {
  const double* cols[kLuPanel];
  double u[kLuPanel];
  int terms = 0;
  for (sunindextype k = k0; k < k_end; ++k) {
    if (col_j[k] == 0.0) continue;
    cols[terms] = a + k * ld;
    u[terms++] = col_j[k];
  }
  if (terms == 0) return;
  sunindextype i = k_end;
  for (; i + 2 <= n; i += 2) {
    Pair t = Load(col_j + i);
    for (int s = 0; s < terms; ++s) t -= u[s] * Load(cols[s] + i);
    Store(col_j + i, t);
  }
  for (; i < n; ++i) {
    double t = col_j[i];
    for (int s = 0; s < terms; ++s) t -= u[s] * cols[s][i];
    col_j[i] = t;
  }
}

// UpdateBelowPanel of two columns of a whole panel whose U entries are all non-zero.
inline void UpdateBelowPanelTwoColumns(sunindextype n, sunindextype ld, const double* a,
                                       sunindextype k0, double* col_j, double* col_j1) {
  const double* l = a + k0 * ld;
  const sunindextype k_end = k0 + kLuPanel;
  double u[kLuPanel], v[kLuPanel];
  for (int s = 0; s < kLuPanel; ++s) {
    u[s] = col_j[k0 + s];
    v[s] = col_j1[k0 + s];
  }
  sunindextype i = k_end;
  for (; i + 2 <= n; i += 2) {
    Pair t = Load(col_j + i), w = Load(col_j1 + i);
    for (int s = 0; s < kLuPanel; ++s) {
      const Pair l_s = Load(l + s * ld + i);
      t -= u[s] * l_s;
      w -= v[s] * l_s;
    }
    Store(col_j + i, t);
    Store(col_j1 + i, w);
  }
  for (; i < n; ++i) {
    double t = col_j[i], w = col_j1[i];
    for (int s = 0; s < kLuPanel; ++s) {
      t -= u[s] * l[s * ld + i];
      w -= v[s] * l[s * ld + i];
    }
    col_j[i] = t;
    col_j1[i] = w;
  }
}

}  // namespace internal

inline sunindextype LuFactorBlocked(sunindextype n, sunindextype ld, double* a,
                                    sunindextype* pivots) {
  using namespace internal;
  for (sunindextype k0 = 0; k0 < n; k0 += kLuPanel) {
    const sunindextype k_end = std::min<sunindextype>(k0 + kLuPanel, n);
    for (sunindextype k = k0; k < k_end; ++k) {
      if (const sunindextype zero = LuStep(n, ld, a, pivots, k, k_end)) return zero;
    }
    for (sunindextype j = k_end; j < n; ++j) {
      double* col_j = a + j * ld;
      UpdatePanelRows(ld, a, k0, k_end, col_j);
      // Two columns whose panel rows are all non-zero (the usual dense case) share the
      // loads of the multipliers.
      if (j + 1 < n && kLuPanel == k_end - k0) {
        double* col_j1 = col_j + ld;
        UpdatePanelRows(ld, a, k0, k_end, col_j1);
        if (NoZeroIn(col_j + k0) && NoZeroIn(col_j1 + k0)) {
          UpdateBelowPanelTwoColumns(n, ld, a, k0, col_j, col_j1);
          ++j;
          continue;
        }
        UpdateBelowPanel(n, ld, a, k0, k_end, col_j);
        UpdateBelowPanel(n, ld, a, k0, k_end, col_j1);
        ++j;
        continue;
      }
      UpdateBelowPanel(n, ld, a, k0, k_end, col_j);
    }
  }
  return 0;
}

// Factors the n x n block `a` (leading dimension ld) in place as P a = L U, L unit lower
// triangular; pivots[k] is the row swapped with row k at step k (whole rows of the block).
// Returns 0, or the 1-based column of the first zero pivot (the factorisation stops there).
template <typename Size, typename Stride>
sunindextype LuFactor(Size n, Stride ld, double* a, sunindextype* pivots) {
  if constexpr (std::is_same_v<Size, sunindextype>) {
    if (n >= kLuBlockMin) return LuFactorBlocked(n, ld, a, pivots);
  }
  for (sunindextype k = 0; k < n; ++k) {
    if (const sunindextype zero = LuStep(n, ld, a, pivots, k, n)) return zero;
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
