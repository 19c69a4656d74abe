#include "server/integrate/fast_serial_ops.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "server/integrate/dense_lu.h"
#include "server/integrate/double_pair.h"
#include "server/integrate/structured_dense_solver.h"

namespace mbstream::sundials {

namespace {

// ---- serial vectors ------------------------------------------------------------------------

inline sunindextype Length(N_Vector v) { return NV_LENGTH_S(v); }
inline double* Data(N_Vector v) { return NV_DATA_S(v); }

// Runs body(n) with the vectors' length n: Fixed<12> when it is 12 (the joint-space ODE of a
// 6-DoF arm; the loops unroll), Fixed<13> when 13 (the same with its work appended as a
// quadrature, as every driven run has it), else the runtime value.
template <typename Body>
inline void WithLength(sunindextype n, Body body) {
  if (n == 12) {
    body(Fixed<12>());
  } else if (n == 13) {
    body(Fixed<13>());
  } else {
    body(n);
  }
}

// The 12-element kernels run on six Pairs (double_pair.h); the 13-element ones on six Pairs
// and a double.

// z = op(x, y) element by element (op takes doubles or Pairs); z may be x or y.
template <typename Op>
inline void Map(sunindextype n, const double* x, const double* y, double* z, Op op) {
  if (n == 12 || n == 13) {
    for (int i = 0; i < 12; i += 2) Store(z + i, op(Load(x + i), Load(y + i)));
    if (n == 13) z[12] = op(x[12], y[12]);
  } else {
    for (sunindextype i = 0; i < n; ++i) z[i] = op(x[i], y[i]);
  }
}

// z = a x + b y. Of CVODE's calls (20 a step) most have a = b = 1 (the predictor, with z = x,
// q (q + 1) / 2 a step; the Newton update) and most others b = 1 (the Newton residual):
// multiplying by 1 is exact, so skipping it gives the plain formula's bits.
void LinearSum(double a, N_Vector x, double b, N_Vector y, N_Vector z) {
  const sunindextype n = Length(z);
  const double* xd = Data(x);
  const double* yd = Data(y);
  double* zd = Data(z);
  if (b == 1.0) {
    if (a == 1.0) {
      Map(n, xd, yd, zd, [](auto xi, auto yi) { return xi + yi; });
    } else {
      Map(n, xd, yd, zd, [a](auto xi, auto yi) { return a * xi + yi; });
    }
  } else {
    Map(n, xd, yd, zd, [a, b](auto xi, auto yi) { return a * xi + b * yi; });
  }
}

void Const(double c, N_Vector z) {
  double* zd = Data(z);
  WithLength(Length(z), [&](auto n) { std::fill(zd, zd + n, c); });
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

void Scale(double c, N_Vector x, N_Vector z) {
  const double* xd = Data(x);
  Map(Length(z), xd, xd, Data(z), [c](auto xi, auto) { return c * xi; });
}

// Abs, Inv and AddConst: once a step each, for the error weights.
void Abs(N_Vector x, N_Vector z) {
  const double* xd = Data(x);
  double* zd = Data(z);
  WithLength(Length(z), [&](auto n) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = std::abs(xd[i]);
  });
}

void Inv(N_Vector x, N_Vector z) {
  const double* xd = Data(x);
  Map(Length(z), xd, xd, Data(z), [](auto xi, auto) { return 1.0 / xi; });
}

void AddConst(N_Vector x, double b, N_Vector z) {
  const double* xd = Data(x);
  Map(Length(z), xd, xd, Data(z), [b](auto xi, auto) { return xi + b; });
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
  if (n == 12) return WSqrSumN<12>(n, Data(x), Data(w));
  return n == 13 ? WSqrSumN<13>(n, Data(x), Data(w)) : WSqrSumN<0>(n, Data(x), Data(w));
}

}  // namespace

double ErrorNorm(N_Vector x, N_Vector w) {
  const sunindextype n = ErrorControlledLength(Length(w), Data(w));
  if (n == 0) return 0.0;
  const double sum = n == 12 ? WSqrSumN<12>(n, Data(x), Data(w)) : WSqrSumN<0>(n, Data(x), Data(w));
  return std::sqrt(sum / static_cast<double>(n));
}

namespace {

double WrmsNorm(N_Vector x, N_Vector w) { return ErrorNorm(x, w); }

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

// z = sum_k c[k] X[k], summed in k order (CVodeGetDky, once an output); any X[k] may be z.
int LinearCombination(int nvec, double* c, N_Vector* X, N_Vector z) {
  const sunindextype n = Length(z);
  double* zd = Data(z);
  if (n != 12 && n != 13) {
    // Two elements at a time, every term summed in a register pair before the store (z may
    // be any X[k]); the vectors' data pointers read once.
    constexpr int kMaxTerms = 16;  // CVODE passes at most q_max + 1 = 6 (BDF), ARKODE 8
    const double* x[kMaxTerms];
    const int terms = std::min(nvec, kMaxTerms);
    for (int k = 0; k < terms; ++k) x[k] = Data(X[k]);
    sunindextype i = 0;
    if (nvec <= kMaxTerms) {
      for (; i + 2 <= n; i += 2) {
        Pair sum = c[0] * Load(x[0] + i);
        for (int k = 1; k < nvec; ++k) sum += c[k] * Load(x[k] + i);
        Store(zd + i, sum);
      }
    }
    for (; i < n; ++i) {
      double sum = c[0] * Data(X[0])[i];
      for (int k = 1; k < nvec; ++k) sum += c[k] * Data(X[k])[i];
      zd[i] = sum;
    }
    return 0;
  }
  // Term by term into six pairs of sums (the same operations per element, in registers),
  // and for 13 elements one more sum; every store after every load (z may be any X[k]).
  Pair sum[6];
  const double* x0 = Data(X[0]);
  for (int p = 0; p < 6; ++p) sum[p] = c[0] * Load(x0 + 2 * p);
  double last = n == 13 ? c[0] * x0[12] : 0.0;
  for (int k = 1; k < nvec; ++k) {
    const double* xk = Data(X[k]);
    for (int p = 0; p < 6; ++p) sum[p] += c[k] * Load(xk + 2 * p);
    if (n == 13) last += c[k] * xk[12];
  }
  for (int p = 0; p < 6; ++p) Store(zd + 2 * p, sum[p]);
  if (n == 13) zd[12] = last;
  return 0;
}

// Z[k] = a[k] x + Y[k] (cvCompleteStep, q + 1 terms with Z = Y: the Nordsieck history).
int ScaleAddMulti(int nvec, double* a, N_Vector x, N_Vector* Y, N_Vector* Z) {
  const sunindextype n = Length(x);
  const double* xd = Data(x);
  for (int k = 0; k < nvec; ++k) {
    Map(n, xd, Data(Y[k]), Data(Z[k]), [ak = a[k]](auto xi, auto yi) { return ak * xi + yi; });
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

// ---- dense LU --------------------------------------------------------------------------------

// The structured (Schur complement) factorisation when the matrix has the form of a
// second-order ODE's Newton matrix, else SUNDIALS' full LU; the solve follows the pivots.
int LuSetup(SUNLinearSolver S, SUNMatrix A) {
  auto* content = static_cast<SUNLinearSolverContent_Dense>(S->content);
  if (SM_ROWS_D(A) != SM_COLUMNS_D(A)) return SUNLS_ILL_INPUT;
  const sunindextype n = SM_COLUMNS_D(A);
  double* a = SM_DATA_D(A);
  sunindextype* pivots = content->pivots;
  sunindextype zero_pivot = FactorStructured(n, a, pivots);
  if (zero_pivot == kNotStructured) {
    // A full LU that stops at a zero pivot leaves the later pivots unwritten: mark the last
    // one as a full LU's first, so IsStructuredFactor never reads uninitialised memory.
    if (n >= 1) pivots[n - 1] = 0;
    zero_pivot =
        n == 12 ? LuFactor(Fixed<12>(), Fixed<12>(), a, pivots) : LuFactor(n, n, a, pivots);
  }
  content->last_flag = zero_pivot;
  return zero_pivot > 0 ? SUNLS_LUFACT_FAIL : SUNLS_SUCCESS;
}

// x = A^-1 b with the factors of a full LU.
void Substitute(sunindextype n, const double* a, const sunindextype* pivots, const double* b,
                double* x) {
  if (n == 12) {  // in a local copy, which the compiler need not reload after every store
    double v[12];
    std::copy(b, b + 12, v);
    LuSubstitute(Fixed<12>(), Fixed<12>(), a, pivots, v);
    std::copy(v, v + 12, x);
  } else {
    if (x != b) std::copy(b, b + n, x);
    LuSubstitute(n, n, a, pivots, x);
  }
}

int LuSolve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, double /*tol*/) {
  auto* content = static_cast<SUNLinearSolverContent_Dense>(S->content);
  const sunindextype n = SM_COLUMNS_D(A);
  const double* a = SM_DATA_D(A);
  const sunindextype* pivots = content->pivots;
  if (IsStructuredFactor(n, pivots)) {
    SolveStructured(n, a, pivots, Data(b), Data(x));
  } else {
    Substitute(n, a, pivots, Data(b), Data(x));
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

void InstallErrorNorm(N_Vector vector) {
  vector->ops->nvwrmsnorm = WrmsNorm;
  vector->ops->nvwrmsnormvectorarray = WrmsNormVectorArray;
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
