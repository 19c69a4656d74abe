#include "server/integrate/structured_dense_solver.h"

#include <algorithm>
#include <type_traits>

#include "server/integrate/dense_lu.h"

namespace mbstream::sundials {

namespace {

// The top half of the n x n matrix `a` (n = 2 m) is [I, c I], exactly: returns c, read from
// entry (0, m), through `c`.
template <typename Half>
bool HasIdentityTop(Half m, const double* a, double* c) {
  const sunindextype n = 2 * m;
  *c = a[m * n];
  for (sunindextype j = 0; j < m; ++j) {
    const double* left = a + j * n;         // column j of M11
    const double* right = a + (m + j) * n;  // column j of M12
    for (sunindextype i = 0; i < m; ++i) {
      if (left[i] != (i == j ? 1.0 : 0.0) || right[i] != (i == j ? *c : 0.0)) return false;
    }
  }
  return true;
}

// Fixed<m>: the solve works in a local array, which the compiler need not reload after every
// store (as it must `x`, which might alias `a`); else in place.
template <typename Half>
constexpr bool kLocal = !std::is_same_v<Half, sunindextype>;

template <typename Half>
sunindextype Factor(Half m, double* a, sunindextype* pivots) {
  const sunindextype n = 2 * m;
  double c;
  if (!HasIdentityTop(m, a, &c)) return kNotStructured;
  const double* m21 = a + m;
  double* m22 = a + m * n + m;
  pivots[m] = kStructuredMark;
  for (sunindextype j = 0; j < m; ++j) {
    for (sunindextype i = 0; i < m; ++i) m22[j * n + i] -= c * m21[j * n + i];
  }
  const sunindextype zero_pivot = LuFactor(m, n, m22, pivots);
  return zero_pivot > 0 ? m + zero_pivot : 0;
}

// Overwrites v (2 m entries) with M^-1 v: v2 -= M21 v1, v2 = S^-1 v2, v1 -= c v2.
template <typename Half>
void SolveInPlace(Half m, const double* a, const sunindextype* pivots, double* v) {
  const sunindextype n = 2 * m;
  const double* m21 = a + m;
  double* v2 = v + m;
  for (sunindextype j = 0; j < m; ++j) {
    const double v1j = v[j];
    for (sunindextype i = 0; i < m; ++i) v2[i] -= m21[j * n + i] * v1j;
  }
  LuSubstitute(m, n, a + m * n + m, pivots, v2);
  const double c = a[m * n];
  for (sunindextype i = 0; i < m; ++i) v[i] -= c * v2[i];
}

template <typename Half>
void Solve(Half m, const double* a, const sunindextype* pivots, const double* b, double* x) {
  if constexpr (kLocal<Half>) {
    double v[2 * Half::value];
    std::copy(b, b + 2 * m, v);
    SolveInPlace(m, a, pivots, v);
    std::copy(v, v + 2 * m, x);
  } else {
    if (x != b) std::copy(b, b + 2 * m, x);
    SolveInPlace(m, a, pivots, x);
  }
}

}  // namespace

sunindextype FactorStructured(sunindextype n, double* a, sunindextype* pivots) {
  if (n == 12) return Factor(Fixed<6>(), a, pivots);
  if (n < 2 || n % 2 != 0) return kNotStructured;
  return Factor(n / 2, a, pivots);
}

void SolveStructured(sunindextype n, const double* a, const sunindextype* pivots, const double* b,
                     double* x) {
  if (n == 12) {
    Solve(Fixed<6>(), a, pivots, b, x);
  } else {
    Solve(n / 2, a, pivots, b, x);
  }
}

}  // namespace mbstream::sundials
