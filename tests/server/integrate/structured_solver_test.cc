// The dense linear solver's structured path (server/integrate/structured_dense_solver.h): a
// Newton matrix of the form [I, c I; M21, M22] is factored through its Schur complement and
// solved to the accuracy of a dense reference LU; other matrices take the full LU; a singular
// Schur complement is reported, as a zero pivot.
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <Eigen/Dense>

#include "server/integrate/fast_serial_ops.h"
#include "server/integrate/structured_dense_solver.h"
#include "server/integrate/sundials_handles.h"

namespace mbstream::sundials {
namespace {

// A SUNDenseMatrix and a SUNLinSol_Dense with the project's operations installed, as
// CvodeIntegrator sets them up.
class DenseSolver {
 public:
  explicit DenseSolver(int n)
      : n_(n),
        context_(MakeContext()),
        a_(SUNDenseMatrix(n, n, context_.get())),
        jacobian_(SUNDenseMatrix(n, n, context_.get())),
        x_(N_VNew_Serial(n, context_.get())),
        b_(N_VNew_Serial(n, context_.get())),
        solver_(SUNLinSol_Dense(x_.get(), a_.get(), context_.get())) {
    InstallFastSerialOps(x_.get());
    InstallFastSerialOps(b_.get());
    InstallFastDenseMatrixOps(a_.get());
    InstallFastDenseMatrixOps(jacobian_.get());
    InstallFastDenseSolverOps(solver_.get());
  }

  // The matrix to factor (column-major n x n).
  void SetMatrix(const Eigen::MatrixXd& m) {
    std::copy(m.data(), m.data() + n_ * n_, SUNDenseMatrix_Data(a_.get()));
  }

  // CVODE's Newton matrix I - gamma J, formed as cvLsSetup forms it: a copy of J, then
  // SUNMatScaleAddI(-gamma, .).
  void SetNewtonMatrix(const Eigen::MatrixXd& jacobian, double gamma) {
    std::copy(jacobian.data(), jacobian.data() + n_ * n_, SUNDenseMatrix_Data(jacobian_.get()));
    ASSERT_EQ(SUNMatCopy(jacobian_.get(), a_.get()), SUNMAT_SUCCESS);
    ASSERT_EQ(SUNMatScaleAddI(-gamma, a_.get()), SUNMAT_SUCCESS);
  }

  int Setup() { return SUNLinSolSetup(solver_.get(), a_.get()); }

  // x = A^-1 b after a successful Setup; in place (x = b) when `in_place`.
  Eigen::VectorXd Solve(const Eigen::VectorXd& b, bool in_place = false) {
    std::copy(b.data(), b.data() + n_, N_VGetArrayPointer(b_.get()));
    N_Vector x = in_place ? b_.get() : x_.get();
    EXPECT_EQ(SUNLinSolSolve(solver_.get(), a_.get(), x, b_.get(), 0.0), SUNLS_SUCCESS);
    return Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(x), n_);
  }

  bool Structured() const {
    auto* content = static_cast<SUNLinearSolverContent_Dense>(solver_->content);
    return IsStructuredFactor(n_, content->pivots);
  }
  sunindextype LastFlag() const { return SUNLinSolLastFlag(solver_.get()); }

 private:
  static Context MakeContext() {
    SUNContext context = nullptr;
    EXPECT_EQ(SUNContext_Create(nullptr, &context), 0);
    return Context(context);
  }

  int n_;
  Context context_;
  Matrix a_;
  Matrix jacobian_;
  Vector x_;
  Vector b_;
  LinearSolver solver_;
};

Eigen::MatrixXd RandomMatrix(int rows, int cols, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd m(rows, cols);
  for (int j = 0; j < cols; ++j) {
    for (int i = 0; i < rows; ++i) m(i, j) = uniform(rng);
  }
  return m;
}

Eigen::VectorXd RandomVector(int n, std::mt19937& rng) { return RandomMatrix(n, 1, rng); }

// The Jacobian of y = [q; qd], q' = qd: [0 I; A B], with a damped, stiff-ish A and B.
Eigen::MatrixXd SecondOrderJacobian(int half, std::mt19937& rng) {
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(2 * half, 2 * half);
  jacobian.topRightCorner(half, half).setIdentity();
  jacobian.bottomLeftCorner(half, half) =
      -400.0 * Eigen::MatrixXd::Identity(half, half) + 50.0 * RandomMatrix(half, half, rng);
  jacobian.bottomRightCorner(half, half) =
      -40.0 * Eigen::MatrixXd::Identity(half, half) + 5.0 * RandomMatrix(half, half, rng);
  return jacobian;
}

double RelativeError(const Eigen::VectorXd& x, const Eigen::VectorXd& reference) {
  return (x - reference).norm() / reference.norm();
}

// A structured matrix [I, c I; M21, M22] with a well-conditioned Schur complement.
Eigen::MatrixXd StructuredMatrix(int half, double c, std::mt19937& rng) {
  const int n = 2 * half;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  m.topLeftCorner(half, half).setIdentity();
  m.topRightCorner(half, half) = c * Eigen::MatrixXd::Identity(half, half);
  m.bottomLeftCorner(half, half) = RandomMatrix(half, half, rng);
  m.bottomRightCorner(half, half) =
      3.0 * Eigen::MatrixXd::Identity(half, half) + RandomMatrix(half, half, rng);
  return m;
}

class StructuredSolverSizes : public ::testing::TestWithParam<int> {};

TEST_P(StructuredSolverSizes, NewtonMatrixOfSecondOrderOdeMatchesDenseLu) {
  const int n = GetParam();
  std::mt19937 rng(20240 + n);
  DenseSolver solver(n);
  for (double gamma : {1e-4, 3e-3, 0.05, 0.4}) {
    const Eigen::MatrixXd jacobian = SecondOrderJacobian(n / 2, rng);
    const Eigen::MatrixXd newton = Eigen::MatrixXd::Identity(n, n) - gamma * jacobian;
    solver.SetNewtonMatrix(jacobian, gamma);
    ASSERT_EQ(solver.Setup(), SUNLS_SUCCESS) << "gamma " << gamma;
    EXPECT_EQ(solver.LastFlag(), 0);
    EXPECT_TRUE(solver.Structured()) << "gamma " << gamma;
    const Eigen::PartialPivLU<Eigen::MatrixXd> reference(newton);
    for (int k = 0; k < 3; ++k) {  // several right-hand sides per factorisation, as Newton
      const Eigen::VectorXd b = RandomVector(n, rng);
      const Eigen::VectorXd expected = reference.solve(b);
      EXPECT_LT(RelativeError(solver.Solve(b), expected), 1e-12) << "gamma " << gamma;
      EXPECT_LT(RelativeError(solver.Solve(b, /*in_place=*/true), expected), 1e-12);
    }
  }
}

TEST_P(StructuredSolverSizes, RandomStructuredMatrixMatchesDenseLu) {
  const int n = GetParam();
  std::mt19937 rng(777 + n);
  DenseSolver solver(n);
  for (double c : {-0.3, 0.0, 1.7}) {
    const Eigen::MatrixXd m = StructuredMatrix(n / 2, c, rng);
    solver.SetMatrix(m);
    ASSERT_EQ(solver.Setup(), SUNLS_SUCCESS);
    EXPECT_TRUE(solver.Structured());
    const Eigen::VectorXd b = RandomVector(n, rng);
    EXPECT_LT(RelativeError(solver.Solve(b), m.partialPivLu().solve(b)), 1e-12) << "c " << c;
  }
}

TEST_P(StructuredSolverSizes, SingularSchurComplementReportsZeroPivot) {
  const int n = GetParam();
  const int half = n / 2;
  std::mt19937 rng(4242 + n);
  const double c = -0.25;
  for (int column : {0, half - 1}) {
    Eigen::MatrixXd m = StructuredMatrix(half, c, rng);
    // Column `column` of S = M22 - c M21 is exactly zero: M (and S) are singular.
    m.col(half + column).tail(half) = c * m.col(column).tail(half);
    DenseSolver solver(n);
    solver.SetMatrix(m);
    EXPECT_EQ(solver.Setup(), SUNLS_LUFACT_FAIL) << "column " << column;
    // The 1-based column of M at which the zero pivot appeared.
    EXPECT_EQ(solver.LastFlag(), half + column + 1);
  }
}

INSTANTIATE_TEST_SUITE_P(Sizes, StructuredSolverSizes, ::testing::Values(2, 12, 20),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return "n" + std::to_string(info.param);
                         });

TEST(StructuredSolverTest, SchurComplementNeedingRowInterchangesIsSolved) {
  for (int n : {4, 12, 20}) {
    const int half = n / 2;
    std::mt19937 rng(31 + n);
    const double c = -0.25;  // c M21 is exact, so M22 - c M21 can cancel to exactly 0
    Eigen::MatrixXd m = StructuredMatrix(half, c, rng);
    // S(0, 0) = 0 exactly: the first pivot must come from another row.
    m(half, half) = c * m(half, 0);
    DenseSolver solver(n);
    solver.SetMatrix(m);
    ASSERT_EQ(solver.Setup(), SUNLS_SUCCESS) << "n " << n;
    EXPECT_TRUE(solver.Structured()) << "n " << n;
    const Eigen::VectorXd b = RandomVector(n, rng);
    EXPECT_LT(RelativeError(solver.Solve(b), m.partialPivLu().solve(b)), 1e-12) << "n " << n;
  }
}

// Appended quadratures add trailing identity rows and columns: the leading block is factored
// and solved as without them, bit for bit, and their part of a solve is the right-hand side.
TEST(StructuredSolverTest, TrailingIdentityRowsAndColumnsLeaveTheSolveBitForBit) {
  for (int half : {6, 10}) {  // 6: the specialised 12 (+ 1 = 13) and generic sizes
    for (int extra : {1, 2}) {
      const int n = 2 * half + extra;
      std::mt19937 rng(61 + n);
      const Eigen::MatrixXd jacobian = SecondOrderJacobian(half, rng);
      Eigen::MatrixXd appended = Eigen::MatrixXd::Zero(n, n);
      appended.topLeftCorner(2 * half, 2 * half) = jacobian;  // Q' rows zero, as appended
      DenseSolver alone(2 * half), with(n);
      alone.SetNewtonMatrix(jacobian, 0.01);
      with.SetNewtonMatrix(appended, 0.01);
      ASSERT_EQ(alone.Setup(), SUNLS_SUCCESS);
      ASSERT_EQ(with.Setup(), SUNLS_SUCCESS) << "n " << n;
      EXPECT_TRUE(with.Structured()) << "n " << n;
      for (bool in_place : {false, true}) {
        const Eigen::VectorXd b = RandomVector(n, rng);
        const Eigen::VectorXd x_alone = alone.Solve(b.head(2 * half), in_place);
        const Eigen::VectorXd x = with.Solve(b, in_place);
        for (int i = 0; i < 2 * half; ++i) ASSERT_EQ(x(i), x_alone(i)) << "n " << n << " i " << i;
        for (int i = 2 * half; i < n; ++i) ASSERT_EQ(x(i), b(i)) << "n " << n << " i " << i;
      }
    }
  }
  // A trailing row that is not the identity's (a quadrature's Jacobian row kept): full LU.
  std::mt19937 rng(62);
  Eigen::MatrixXd m = Eigen::MatrixXd::Identity(13, 13);
  m.topLeftCorner(12, 12) = StructuredMatrix(6, -0.01, rng);
  m(12, 3) = 0.5;
  DenseSolver solver(13);
  solver.SetMatrix(m);
  ASSERT_EQ(solver.Setup(), SUNLS_SUCCESS);
  EXPECT_FALSE(solver.Structured());
  const Eigen::VectorXd b = RandomVector(13, rng);
  EXPECT_LT(RelativeError(solver.Solve(b), m.partialPivLu().solve(b)), 1e-12);
}

TEST(StructuredSolverTest, UnstructuredMatricesUseTheFullLu) {
  std::mt19937 rng(99);
  for (int n : {3, 7, 12, 20}) {
    const Eigen::MatrixXd m =
        4.0 * Eigen::MatrixXd::Identity(n, n) + RandomMatrix(n, n, rng);  // well-conditioned
    DenseSolver solver(n);
    solver.SetMatrix(m);
    ASSERT_EQ(solver.Setup(), SUNLS_SUCCESS) << "n " << n;
    EXPECT_FALSE(solver.Structured()) << "n " << n;
    const Eigen::VectorXd b = RandomVector(n, rng);
    EXPECT_LT(RelativeError(solver.Solve(b), m.partialPivLu().solve(b)), 1e-12) << "n " << n;
    EXPECT_LT(RelativeError(solver.Solve(b, /*in_place=*/true), m.partialPivLu().solve(b)), 1e-12);
  }
}

// One entry of the top half off by one unit in the last place: not the structure.
TEST(StructuredSolverTest, NearlyStructuredMatricesUseTheFullLu) {
  const int n = 12;
  const int half = n / 2;
  std::mt19937 rng(5);
  const struct {
    int row, col;
  } entries[] = {{0, 0}, {half - 1, half - 1}, {2, 3}, {0, half}, {half - 1, n - 1}, {1, half}};
  for (const auto& entry : entries) {
    Eigen::MatrixXd m = StructuredMatrix(half, -0.01, rng);
    const double exact = m(entry.row, entry.col);
    m(entry.row, entry.col) = std::nextafter(exact, std::numeric_limits<double>::infinity());
    ASSERT_NE(m(entry.row, entry.col), exact);
    DenseSolver solver(n);
    solver.SetMatrix(m);
    ASSERT_EQ(solver.Setup(), SUNLS_SUCCESS);
    EXPECT_FALSE(solver.Structured()) << "entry " << entry.row << ", " << entry.col;
    const Eigen::VectorXd b = RandomVector(n, rng);
    EXPECT_LT(RelativeError(solver.Solve(b), m.partialPivLu().solve(b)), 1e-12);
  }
}

TEST(StructuredSolverTest, SingularUnstructuredMatrixReportsZeroPivot) {
  const int n = 12;
  std::mt19937 rng(8);
  Eigen::MatrixXd m = RandomMatrix(n, n, rng);
  m.col(4).setZero();
  DenseSolver solver(n);
  solver.SetMatrix(m);
  EXPECT_EQ(solver.Setup(), SUNLS_LUFACT_FAIL);
  EXPECT_FALSE(solver.Structured());
  EXPECT_EQ(solver.LastFlag(), 5);
}

// FactorStructured leaves a matrix without the structure untouched, for the full LU.
TEST(StructuredSolverTest, FactorStructuredDeclinesWithoutChangingTheMatrix) {
  std::mt19937 rng(12);
  for (int n : {1, 5, 12, 20}) {
    Eigen::MatrixXd m = RandomMatrix(n, n, rng);
    const Eigen::MatrixXd original = m;
    std::vector<sunindextype> pivots(n, 7);
    EXPECT_EQ(FactorStructured(n, m.data(), pivots.data()), kNotStructured) << "n " << n;
    EXPECT_EQ(m, original);
    EXPECT_EQ(pivots, std::vector<sunindextype>(n, 7));
  }
}

}  // namespace
}  // namespace mbstream::sundials
