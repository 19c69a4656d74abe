// The joint-space ODE's Newton linear system for big models (n joints, 2n states): our dense
// solver (structured: the n x n Schur complement; full LU otherwise) and vector kernels
// against SUNDIALS' own dense solver and serial vector, and against Eigen's general LU.
//
//   build/bench/newton_solver_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only
//
// BM_NewtonSetupSolve/<solver>/<n>: one factorisation of M = I - gamma J, J = [0 I; A B],
// and one solve (CVODE solves about 1.2 times per factorisation on seed-servo; the
// factorisation dominates for big n). BM_Vector*/<ops>/<n>: the kernels CVODE calls most,
// on vectors of 2n entries.
#include <benchmark/benchmark.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/Dense>
#include <random>

#include "server/integrate/fast_serial_ops.h"
#include "server/integrate/sundials_handles.h"

namespace mbstream::sundials {
namespace {

// The Newton matrix of a second-order ODE with n joints: M = I - gamma [0 I; A B], A and B
// random with a dominant diagonal (the stiffness and damping slopes of servos on M^-1).
Eigen::MatrixXd NewtonMatrix(int n, bool structured = true) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  J.topRightCorner(n, n).setIdentity();
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      J(n + i, j) = 10.0 * dist(rng) - (i == j ? 400.0 : 0.0);
      J(n + i, n + j) = dist(rng) - (i == j ? 40.0 : 0.0);
    }
  }
  if (!structured) J(0, 0) = 1e-3;  // a top block that is not [0 I]: the full LU
  const double gamma = 0.01;
  return Eigen::MatrixXd::Identity(2 * n, 2 * n) - gamma * J;
}

Eigen::VectorXd RandomVector(int size) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  Eigen::VectorXd v(size);
  for (int i = 0; i < size; ++i) v(i) = dist(rng);
  return v;
}

// ours: SUNLinSol_Dense with the project's operations (CvodeIntegrator's set-up);
// sundials: SUNLinSol_Dense as SUNDIALS ships it (the optimised build's denseGETRF).
void NewtonSetupSolve(benchmark::State& state, bool ours, bool structured = true) {
  const int n = static_cast<int>(state.range(0)), size = 2 * n;
  const Eigen::MatrixXd newton = NewtonMatrix(n, structured);
  const Eigen::VectorXd b = RandomVector(size);
  SUNContext raw_context = nullptr;
  SUNContext_Create(nullptr, &raw_context);
  Context context(raw_context);
  Matrix a(SUNDenseMatrix(size, size, context.get()));
  Vector x(N_VNew_Serial(size, context.get())), rhs(N_VNew_Serial(size, context.get()));
  LinearSolver solver(SUNLinSol_Dense(x.get(), a.get(), context.get()));
  if (ours) {
    InstallFastSerialOps(x.get());
    InstallFastDenseMatrixOps(a.get());
    InstallFastDenseSolverOps(solver.get());
  }
  double* a_data = SUNDenseMatrix_Data(a.get());
  for (auto _ : state) {
    std::copy(newton.data(), newton.data() + newton.size(), a_data);
    std::copy(b.data(), b.data() + size, N_VGetArrayPointer(rhs.get()));
    if (SUNLinSolSetup(solver.get(), a.get()) != SUNLS_SUCCESS) state.SkipWithError("singular");
    SUNLinSolSolve(solver.get(), a.get(), x.get(), rhs.get(), 0.0);
    benchmark::DoNotOptimize(N_VGetArrayPointer(x.get()));
  }
}

void BM_NewtonOurs(benchmark::State& state) { NewtonSetupSolve(state, true); }
void BM_NewtonSundials(benchmark::State& state) { NewtonSetupSolve(state, false); }
// Ours on a matrix without the structure: the fallback, a full LU of 2n x 2n.
void BM_NewtonOursFullLu(benchmark::State& state) { NewtonSetupSolve(state, true, false); }

// Eigen's general LU with partial pivoting (blocked, with its matrix-product kernels) on the
// whole 2n x 2n matrix: the reference no path of ours may be slower than.
void BM_NewtonEigenPartialPivLu(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Eigen::MatrixXd newton = NewtonMatrix(n);
  const Eigen::VectorXd b = RandomVector(2 * n);
  Eigen::MatrixXd a(2 * n, 2 * n);
  Eigen::PartialPivLU<Eigen::Ref<Eigen::MatrixXd>> lu(a);  // in place, allocated once
  Eigen::VectorXd x(2 * n);
  for (auto _ : state) {
    a = newton;
    lu.compute(a);
    x = lu.solve(b);
    benchmark::DoNotOptimize(x.data());
  }
}

// The vector kernels CVODE calls most (a linear sum, a weighted RMS norm, a linear
// combination of 6 vectors, CVodeGetDky's and the corrector's), on 2n entries.
void VectorKernels(benchmark::State& state, bool ours) {
  const int size = 2 * static_cast<int>(state.range(0));
  SUNContext raw_context = nullptr;
  SUNContext_Create(nullptr, &raw_context);
  Context context(raw_context);
  Vector x(N_VNew_Serial(size, context.get()));
  if (ours) {
    InstallFastSerialOps(x.get());
  } else {
    N_VEnableFusedOps_Serial(x.get(), SUNTRUE);
  }
  std::vector<Vector> v;
  N_Vector raw[6];
  double c[6] = {1.0, -0.5, 0.25, 0.125, -2.0, 3.0};
  for (int k = 0; k < 6; ++k) {
    v.emplace_back(N_VClone(x.get()));
    raw[k] = v.back().get();
    const Eigen::VectorXd r = RandomVector(size);
    std::copy(r.data(), r.data() + size, N_VGetArrayPointer(raw[k]));
  }
  N_VConst(1e-3, x.get());
  for (auto _ : state) {
    N_VLinearSum(1.0, raw[0], -0.7, raw[1], raw[2]);
    benchmark::DoNotOptimize(N_VWrmsNorm(raw[2], x.get()));
    N_VLinearCombination(6, c, raw, raw[5]);
    benchmark::DoNotOptimize(N_VGetArrayPointer(raw[5]));
  }
}

void BM_VectorOurs(benchmark::State& state) { VectorKernels(state, true); }
void BM_VectorSundials(benchmark::State& state) { VectorKernels(state, false); }

void Sizes(benchmark::internal::Benchmark* b) {
  for (int n : {6, 20, 50, 100, 200}) b->Arg(n);
}
BENCHMARK(BM_NewtonOurs)->Apply(Sizes);
BENCHMARK(BM_NewtonOursFullLu)->Apply(Sizes);
BENCHMARK(BM_NewtonSundials)->Apply(Sizes);
BENCHMARK(BM_NewtonEigenPartialPivLu)->Apply(Sizes);
BENCHMARK(BM_VectorOurs)->Apply(Sizes);
BENCHMARK(BM_VectorSundials)->Apply(Sizes);

}  // namespace
}  // namespace mbstream::sundials

BENCHMARK_MAIN();
