#include "server/integrate/structured_dense_solver.h"

#include <algorithm>
#include <type_traits>

#include "server/integrate/dense_lu.h"

namespace mbstream::sundials {

namespace {

// The top half of the leading 2m x 2m block of `a` (leading dimension ld) is [I, c I],
// exactly: returns c, read from entry (0, m), through `c`.
template <typename Half, typename Lead>
bool HasIdentityTop(Half m, Lead ld, const double* a, double* c) {
  *c = a[m * ld];
  for (sunindextype j = 0; j < m; ++j) {
    const double* left = a + j * ld;         // column j of M11
    const double* right = a + (m + j) * ld;  // column j of M12
    for (sunindextype i = 0; i < m; ++i) {
      if (left[i] != (i == j ? 1.0 : 0.0) || right[i] != (i == j ? *c : 0.0)) return false;
    }
  }
  return true;
}

// Row and column j of the n x n matrix `a` are those of the identity, exactly.
bool IsIdentityRowAndColumn(sunindextype n, const double* a, sunindextype j) {
  for (sunindextype i = 0; i < n; ++i) {
    const double expected = i == j ? 1.0 : 0.0;
    if (a[j * n + i] != expected || a[i * n + j] != expected) return false;
  }
  return true;
}

// How many trailing rows and columns of the n x n matrix `a` are the identity's (the
// appended quadratures'), leaving at least two states.
sunindextype TrailingIdentity(sunindextype n, const double* a) {
  sunindextype r = 0;
  while (n - r > 2 && IsIdentityRowAndColumn(n, a, n - 1 - r)) ++r;
  return r;
}

// Fixed<m>: the solve works in a local array, which the compiler need not reload after every
// store (as it must `x`, which might alias `a`); else in place.
template <typename Half>
constexpr bool kLocal = !std::is_same_v<Half, sunindextype>;

template <typename Half, typename Lead>
sunindextype Factor(Half m, Lead ld, double* a, sunindextype* pivots) {
  double c;
  if (!HasIdentityTop(m, ld, a, &c)) return kNotStructured;
  const double* m21 = a + m;
  double* m22 = a + m * ld + m;
  for (sunindextype j = 0; j < m; ++j) {
    for (sunindextype i = 0; i < m; ++i) m22[j * ld + i] -= c * m21[j * ld + i];
  }
  const sunindextype zero_pivot = LuFactor(m, ld, m22, pivots);
  pivots[ld - 1] = StructuredMark(m);
  return zero_pivot > 0 ? m + zero_pivot : 0;
}

// Overwrites v (2 m entries) with M^-1 v: v2 -= M21 v1, v2 = S^-1 v2, v1 -= c v2.
template <typename Half, typename Lead>
void SolveInPlace(Half m, Lead ld, const double* a, const sunindextype* pivots, double* v) {
  const double* m21 = a + m;
  double* v2 = v + m;
  for (sunindextype j = 0; j < m; ++j) {
    const double v1j = v[j];
    for (sunindextype i = 0; i < m; ++i) v2[i] -= m21[j * ld + i] * v1j;
  }
  LuSubstitute(m, ld, a + m * ld + m, pivots, v2);
  const double c = a[m * ld];
  for (sunindextype i = 0; i < m; ++i) v[i] -= c * v2[i];
}

// The leading 2m states through the factors; the trailing ld - 2m (identity) copied.
template <typename Half, typename Lead>
void Solve(Half m, Lead ld, const double* a, const sunindextype* pivots, const double* b,
           double* x) {
  if constexpr (kLocal<Half>) {
    double v[2 * Half::value];
    std::copy(b, b + 2 * m, v);
    SolveInPlace(m, ld, a, pivots, v);
    std::copy(v, v + 2 * m, x);
  } else {
    if (x != b) std::copy(b, b + 2 * m, x);
    SolveInPlace(m, ld, a, pivots, x);
  }
  if (x != b) std::copy(b + 2 * m, b + ld, x + 2 * m);
}

}  // namespace

sunindextype FactorStructured(sunindextype n, double* a, sunindextype* pivots) {
  if (n == 12) return Factor(Fixed<6>(), Fixed<12>(), a, pivots);
  if (n < 2) return kNotStructured;
  const sunindextype leading = n - TrailingIdentity(n, a);
  if (leading % 2 != 0) return kNotStructured;
  if (leading == 12 && n == 13) return Factor(Fixed<6>(), Fixed<13>(), a, pivots);
  return Factor(leading / 2, n, a, pivots);
}

void SolveStructured(sunindextype n, const double* a, const sunindextype* pivots, const double* b,
                     double* x) {
  const sunindextype m = -pivots[n - 1] - 1;
  if (n == 12) {
    Solve(Fixed<6>(), Fixed<12>(), a, pivots, b, x);
  } else if (n == 13 && m == 6) {
    Solve(Fixed<6>(), Fixed<13>(), a, pivots, b, x);
  } else {
    Solve(m, n, a, pivots, b, x);
  }
}

}  // namespace mbstream::sundials
