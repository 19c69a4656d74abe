#include "server/integrate/fast_serial_ops.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

namespace mbstream::sundials {

namespace {

// ---- serial vectors ------------------------------------------------------------------------

inline sunindextype Length(N_Vector v) { return NV_LENGTH_S(v); }
inline double* Data(N_Vector v) { return NV_DATA_S(v); }

// z = a x + b y for kN > 0 elements (known at compile time: the loop unrolls) or n.
template <int kN>
inline void LinearSumN(sunindextype runtime_n, double a, const double* x, double b, const double* y,
                       double* z) {
  const sunindextype n = kN > 0 ? kN : runtime_n;
  for (sunindextype i = 0; i < n; ++i) z[i] = a * x[i] + b * y[i];
}

// CVODE's predictor and corrector call this some 25 times per step.
void LinearSum(double a, N_Vector x, double b, N_Vector y, N_Vector z) {
  const sunindextype n = Length(z);
  if (n == 12) {
    LinearSumN<12>(n, a, Data(x), b, Data(y), Data(z));
  } else {
    LinearSumN<0>(n, a, Data(x), b, Data(y), Data(z));
  }
}

void Const(double c, N_Vector z) {
  double* zd = Data(z);
  std::fill(zd, zd + Length(z), c);
}

void Prod(N_Vector x, N_Vector y, N_Vector z) {
  const sunindextype n = Length(z);
  const double* xd = Data(x);
  const double* yd = Data(y);
  double* zd = Data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] * yd[i];
}

void Div(N_Vector x, N_Vector y, N_Vector z) {
  const sunindextype n = Length(z);
  const double* xd = Data(x);
  const double* yd = Data(y);
  double* zd = Data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] / yd[i];
}

template <int kN>
inline void ScaleN(sunindextype runtime_n, double c, const double* x, double* z) {
  const sunindextype n = kN > 0 ? kN : runtime_n;
  for (sunindextype i = 0; i < n; ++i) z[i] = c * x[i];
}

void Scale(double c, N_Vector x, N_Vector z) {
  const sunindextype n = Length(z);
  if (n == 12) {
    ScaleN<12>(n, c, Data(x), Data(z));
  } else {
    ScaleN<0>(n, c, Data(x), Data(z));
  }
}

void Abs(N_Vector x, N_Vector z) {
  const sunindextype n = Length(z);
  const double* xd = Data(x);
  double* zd = Data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = std::abs(xd[i]);
}

void Inv(N_Vector x, N_Vector z) {
  const sunindextype n = Length(z);
  const double* xd = Data(x);
  double* zd = Data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = 1.0 / xd[i];
}

void AddConst(N_Vector x, double b, N_Vector z) {
  const sunindextype n = Length(z);
  const double* xd = Data(x);
  double* zd = Data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] + b;
}

double DotProd(N_Vector x, N_Vector y) {
  const sunindextype n = Length(x);
  const double* xd = Data(x);
  const double* yd = Data(y);
  double sum = 0.0;
  for (sunindextype i = 0; i < n; ++i) sum += xd[i] * yd[i];
  return sum;
}

double MaxNorm(N_Vector x) {
  const sunindextype n = Length(x);
  const double* xd = Data(x);
  double max = 0.0;
  for (sunindextype i = 0; i < n; ++i) max = std::max(max, std::abs(xd[i]));
  return max;
}

template <int kN>
inline double WSqrSumN(sunindextype runtime_n, const double* x, const double* w) {
  const sunindextype n = kN > 0 ? kN : runtime_n;
  double sum = 0.0;
  for (sunindextype i = 0; i < n; ++i) {
    const double p = x[i] * w[i];
    sum += p * p;
  }
  return sum;
}

double WSqrSum(N_Vector x, N_Vector w) {
  const sunindextype n = Length(x);
  return n == 12 ? WSqrSumN<12>(n, Data(x), Data(w)) : WSqrSumN<0>(n, Data(x), Data(w));
}

double WrmsNorm(N_Vector x, N_Vector w) {
  return std::sqrt(WSqrSum(x, w) / static_cast<double>(Length(x)));
}

double Min(N_Vector x) {
  const sunindextype n = Length(x);
  const double* xd = Data(x);
  double min = xd[0];
  for (sunindextype i = 1; i < n; ++i) min = std::min(min, xd[i]);
  return min;
}

void Compare(double c, N_Vector x, N_Vector z) {
  const sunindextype n = Length(z);
  const double* xd = Data(x);
  double* zd = Data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = std::abs(xd[i]) >= c ? 1.0 : 0.0;
}

sunbooleantype InvTest(N_Vector x, N_Vector z) {
  const sunindextype n = Length(z);
  const double* xd = Data(x);
  double* zd = Data(z);
  sunbooleantype no_zero = SUNTRUE;
  for (sunindextype i = 0; i < n; ++i) {
    if (xd[i] == 0.0) {
      no_zero = SUNFALSE;
    } else {
      zd[i] = 1.0 / xd[i];
    }
  }
  return no_zero;
}

// z = sum_k c[k] X[k]; element by element, so any X[k] may be z.
int LinearCombination(int nvec, double* c, N_Vector* X, N_Vector z) {
  const sunindextype n = Length(z);
  double* zd = Data(z);
  for (sunindextype i = 0; i < n; ++i) {
    double sum = c[0] * Data(X[0])[i];
    for (int k = 1; k < nvec; ++k) sum += c[k] * Data(X[k])[i];
    zd[i] = sum;
  }
  return 0;
}

// Z[k] = a[k] x + Y[k].
int ScaleAddMulti(int nvec, double* a, N_Vector x, N_Vector* Y, N_Vector* Z) {
  const sunindextype n = Length(x);
  for (int k = 0; k < nvec; ++k) {
    if (n == 12) {
      LinearSumN<12>(n, a[k], Data(x), 1.0, Data(Y[k]), Data(Z[k]));
    } else {
      LinearSumN<0>(n, a[k], Data(x), 1.0, Data(Y[k]), Data(Z[k]));
    }
  }
  return 0;
}

// Z[k] = a X[k] + b Y[k].
int LinearSumVectorArray(int nvec, double a, N_Vector* X, double b, N_Vector* Y, N_Vector* Z) {
  for (int k = 0; k < nvec; ++k) LinearSum(a, X[k], b, Y[k], Z[k]);
  return 0;
}

// Z[k] = c[k] X[k].
int ScaleVectorArray(int nvec, double* c, N_Vector* X, N_Vector* Z) {
  for (int k = 0; k < nvec; ++k) Scale(c[k], X[k], Z[k]);
  return 0;
}

int ConstVectorArray(int nvec, double c, N_Vector* Z) {
  for (int k = 0; k < nvec; ++k) Const(c, Z[k]);
  return 0;
}

int WrmsNormVectorArray(int nvec, N_Vector* X, N_Vector* W, double* norms) {
  for (int k = 0; k < nvec; ++k) norms[k] = WrmsNorm(X[k], W[k]);
  return 0;
}

// ---- dense matrices --------------------------------------------------------------------------

int MatZero(SUNMatrix A) {
  std::memset(SM_DATA_D(A), 0, sizeof(double) * static_cast<size_t>(SM_LDATA_D(A)));
  return SUNMAT_SUCCESS;
}

int MatCopy(SUNMatrix A, SUNMatrix B) {  // B = A
  if (SM_ROWS_D(A) != SM_ROWS_D(B) || SM_COLUMNS_D(A) != SM_COLUMNS_D(B)) {
    return SUNMAT_ILL_INPUT;
  }
  std::memcpy(SM_DATA_D(B), SM_DATA_D(A), sizeof(double) * static_cast<size_t>(SM_LDATA_D(A)));
  return SUNMAT_SUCCESS;
}

int MatScaleAddI(double c, SUNMatrix A) {  // A = c A + I
  const sunindextype rows = SM_ROWS_D(A);
  const sunindextype cols = SM_COLUMNS_D(A);
  double* data = SM_DATA_D(A);
  const sunindextype size = SM_LDATA_D(A);
  for (sunindextype k = 0; k < size; ++k) data[k] *= c;
  for (sunindextype j = 0; j < std::min(rows, cols); ++j) data[j * rows + j] += 1.0;
  return SUNMAT_SUCCESS;
}

SUNMatrix MatClone(SUNMatrix A) {
  SUNMatrix B = SUNMatClone_Dense(A);
  if (B != nullptr) InstallFastDenseMatrixOps(B);
  return B;
}

// ---- dense LU (SUNDIALS' denseGETRF / denseGETRS, column-major) -----------------------------

// kN > 0: the size at compile time (the loops unroll; CVODE's 12-state joint-space ODE calls
// the solve about once per step), else `runtime_n`. Returns 0 or the 1-based column of a
// zero pivot.
template <int kN>
sunindextype Factor(sunindextype runtime_n, double* a, sunindextype* pivots) {
  const sunindextype n = kN > 0 ? kN : runtime_n;
  for (sunindextype k = 0; k < n; ++k) {
    double* col_k = a + k * n;
    sunindextype l = k;
    for (sunindextype i = k + 1; i < n; ++i) {
      if (std::abs(col_k[i]) > std::abs(col_k[l])) l = i;
    }
    pivots[k] = l;
    if (col_k[l] == 0.0) return k + 1;
    if (l != k) {
      for (sunindextype j = 0; j < n; ++j) std::swap(a[j * n + l], a[j * n + k]);
    }
    const double mult = 1.0 / col_k[k];
    for (sunindextype i = k + 1; i < n; ++i) col_k[i] *= mult;
    for (sunindextype j = k + 1; j < n; ++j) {
      double* col_j = a + j * n;
      const double a_kj = col_j[k];
      if (a_kj != 0.0) {
        for (sunindextype i = k + 1; i < n; ++i) col_j[i] -= a_kj * col_k[i];
      }
    }
  }
  return 0;
}

template <int kN>
void Substitute(sunindextype runtime_n, const double* a, const sunindextype* pivots, double* x) {
  const sunindextype n = kN > 0 ? kN : runtime_n;
  for (sunindextype k = 0; k < n; ++k) {
    if (pivots[k] != k) std::swap(x[k], x[pivots[k]]);
  }
  for (sunindextype k = 0; k < n - 1; ++k) {
    const double* col_k = a + k * n;
    const double xk = x[k];
    for (sunindextype i = k + 1; i < n; ++i) x[i] -= col_k[i] * xk;
  }
  for (sunindextype k = n - 1; k > 0; --k) {
    const double* col_k = a + k * n;
    x[k] /= col_k[k];
    const double xk = x[k];
    for (sunindextype i = 0; i < k; ++i) x[i] -= col_k[i] * xk;
  }
  x[0] /= a[0];
}

int LuSetup(SUNLinearSolver S, SUNMatrix A) {
  auto* content = static_cast<SUNLinearSolverContent_Dense>(S->content);
  if (SM_ROWS_D(A) != SM_COLUMNS_D(A)) return SUNLS_ILL_INPUT;
  const sunindextype n = SM_COLUMNS_D(A);
  double* a = SM_DATA_D(A);
  sunindextype* pivots = content->pivots;
  const sunindextype zero_pivot = n == 12 ? Factor<12>(n, a, pivots) : Factor<0>(n, a, pivots);
  content->last_flag = zero_pivot;
  return zero_pivot > 0 ? SUNLS_LUFACT_FAIL : SUNLS_SUCCESS;
}

int LuSolve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, double /*tol*/) {
  auto* content = static_cast<SUNLinearSolverContent_Dense>(S->content);
  const sunindextype n = SM_COLUMNS_D(A);
  const double* a = SM_DATA_D(A);
  double* xd = Data(x);
  if (x != b) std::copy(Data(b), Data(b) + n, xd);
  if (n == 12) {
    Substitute<12>(n, a, content->pivots, xd);
  } else {
    Substitute<0>(n, a, content->pivots, xd);
  }
  content->last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

}  // namespace

void InstallFastSerialOps(N_Vector vector) {
  N_Vector_Ops ops = vector->ops;
  ops->nvlinearsum = LinearSum;
  ops->nvconst = Const;
  ops->nvprod = Prod;
  ops->nvdiv = Div;
  ops->nvscale = Scale;
  ops->nvabs = Abs;
  ops->nvinv = Inv;
  ops->nvaddconst = AddConst;
  ops->nvdotprod = DotProd;
  ops->nvmaxnorm = MaxNorm;
  ops->nvwrmsnorm = WrmsNorm;
  ops->nvmin = Min;
  ops->nvcompare = Compare;
  ops->nvinvtest = InvTest;
  ops->nvdotprodlocal = DotProd;
  ops->nvmaxnormlocal = MaxNorm;
  ops->nvminlocal = Min;
  ops->nvinvtestlocal = InvTest;
  ops->nvwsqrsumlocal = WSqrSum;
  ops->nvlinearcombination = LinearCombination;
  ops->nvscaleaddmulti = ScaleAddMulti;
  ops->nvlinearsumvectorarray = LinearSumVectorArray;
  ops->nvscalevectorarray = ScaleVectorArray;
  ops->nvconstvectorarray = ConstVectorArray;
  ops->nvwrmsnormvectorarray = WrmsNormVectorArray;
}

void InstallFastDenseMatrixOps(SUNMatrix matrix) {
  SUNMatrix_Ops ops = matrix->ops;
  ops->clone = MatClone;
  ops->zero = MatZero;
  ops->copy = MatCopy;
  ops->scaleaddi = MatScaleAddI;
}

void InstallFastDenseSolverOps(SUNLinearSolver solver) {
  solver->ops->setup = LuSetup;
  solver->ops->solve = LuSolve;
}

}  // namespace mbstream::sundials
