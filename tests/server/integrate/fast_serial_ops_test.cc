// The replacement serial-vector kernels (server/integrate/fast_serial_ops.h) give the plain
// formulas' results bit for bit, for the specialised lengths (12, and 13: with the work appended)
// and others, on every fast path and with the output aliasing an input.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nvector/nvector_serial.h>

#include "server/integrate/fast_serial_ops.h"
#include "server/integrate/sundials_handles.h"

namespace mbstream::sundials {
namespace {

class FastSerialOpsTest : public ::testing::TestWithParam<int> {
 protected:
  FastSerialOpsTest() {
    SUNContext context = nullptr;
    EXPECT_EQ(SUNContext_Create(nullptr, &context), 0);
    context_.reset(context);
  }

  // A vector with the fast operations and random entries (no zeros).
  Vector NewVector() {
    Vector v(N_VNew_Serial(n(), context_.get()));
    InstallFastSerialOps(v.get());
    std::uniform_real_distribution<double> uniform(0.1, 10.0);
    std::bernoulli_distribution negative(0.5);
    for (int i = 0; i < n(); ++i) {
      Data(v.get())[i] = negative(rng_) ? -uniform(rng_) : uniform(rng_);
    }
    return v;
  }

  static double* Data(N_Vector v) { return N_VGetArrayPointer(v); }
  std::vector<double> Copy(N_Vector v) const { return {Data(v), Data(v) + n()}; }
  int n() const { return GetParam(); }

  std::mt19937 rng_{1234};
  Context context_;
};

TEST_P(FastSerialOpsTest, LinearSumMatchesPlainFormulaBitForBit) {
  const double coefficients[][2] = {{1.0, 1.0}, {0.37, 1.0}, {1.0, -1.0}, {-1.0, 1.0},
                                    {1.0, 0.6}, {-2.5, 3.1}, {0.0, 1.0},  {1.0, 0.0}};
  for (const auto& [a, b] : coefficients) {
    for (int alias = 0; alias < 3; ++alias) {  // z separate, z = x, z = y
      Vector x = NewVector(), y = NewVector(), z = NewVector();
      const std::vector<double> xs = Copy(x.get()), ys = Copy(y.get());
      N_Vector out = alias == 0 ? z.get() : alias == 1 ? x.get() : y.get();
      N_VLinearSum(a, x.get(), b, y.get(), out);
      for (int i = 0; i < n(); ++i) {
        ASSERT_EQ(Data(out)[i], a * xs[i] + b * ys[i])
            << "a " << a << " b " << b << " alias " << alias << " i " << i;
      }
    }
  }
}

TEST_P(FastSerialOpsTest, ScaleAddMultiMatchesPlainFormulaBitForBit) {
  Vector x = NewVector();
  std::vector<Vector> ys;
  std::vector<N_Vector> y_ptrs, z_ptrs;
  std::vector<std::vector<double>> y_values;
  std::vector<Vector> zs;
  double a[6] = {1.0, -0.5, 2.25, 1e-3, -7.0, 0.3};
  for (int k = 0; k < 6; ++k) {
    ys.push_back(NewVector());
    y_values.push_back(Copy(ys.back().get()));
    y_ptrs.push_back(ys.back().get());
    zs.push_back(NewVector());
    z_ptrs.push_back(k % 2 == 0 ? ys.back().get() : zs.back().get());  // Z[k] = Y[k] or not
  }
  const std::vector<double> xs = Copy(x.get());
  ASSERT_EQ(N_VScaleAddMulti(6, a, x.get(), y_ptrs.data(), z_ptrs.data()), 0);
  for (int k = 0; k < 6; ++k) {
    for (int i = 0; i < n(); ++i) {
      ASSERT_EQ(Data(z_ptrs[k])[i], a[k] * xs[i] + y_values[k][i]) << "k " << k << " i " << i;
    }
  }
}

TEST_P(FastSerialOpsTest, LinearCombinationMatchesPlainFormulaBitForBit) {
  for (int out_index = -1; out_index < 5; ++out_index) {  // z separate, or z = X[out_index]
    std::vector<Vector> xs;
    std::vector<N_Vector> x_ptrs;
    std::vector<std::vector<double>> values;
    for (int k = 0; k < 5; ++k) {
      xs.push_back(NewVector());
      x_ptrs.push_back(xs.back().get());
      values.push_back(Copy(xs.back().get()));
    }
    double c[5] = {0.5, -1.25, 3.0, 1e-2, 1.0};
    Vector z = NewVector();
    N_Vector out = out_index < 0 ? z.get() : x_ptrs[out_index];
    ASSERT_EQ(N_VLinearCombination(5, c, x_ptrs.data(), out), 0);
    for (int i = 0; i < n(); ++i) {
      double sum = c[0] * values[0][i];
      for (int k = 1; k < 5; ++k) sum += c[k] * values[k][i];
      ASSERT_EQ(Data(out)[i], sum) << "out " << out_index << " i " << i;
    }
  }
}

TEST_P(FastSerialOpsTest, ElementwiseKernelsMatchPlainFormulasBitForBit) {
  Vector x = NewVector(), z = NewVector();
  const std::vector<double> xs = Copy(x.get());
  N_VScale(-0.3, x.get(), z.get());
  for (int i = 0; i < n(); ++i) ASSERT_EQ(Data(z.get())[i], -0.3 * xs[i]);
  N_VInv(x.get(), z.get());
  for (int i = 0; i < n(); ++i) ASSERT_EQ(Data(z.get())[i], 1.0 / xs[i]);
  N_VAddConst(x.get(), 0.7, z.get());
  for (int i = 0; i < n(); ++i) ASSERT_EQ(Data(z.get())[i], xs[i] + 0.7);
  N_VAbs(x.get(), z.get());
  for (int i = 0; i < n(); ++i) ASSERT_EQ(Data(z.get())[i], std::abs(xs[i]));
  N_VConst(2.5, z.get());
  for (int i = 0; i < n(); ++i) ASSERT_EQ(Data(z.get())[i], 2.5);
  N_VScale(4.0, x.get(), x.get());  // in place
  for (int i = 0; i < n(); ++i) ASSERT_EQ(Data(x.get())[i], 4.0 * xs[i]);
}

TEST_P(FastSerialOpsTest, WrmsNormMatchesPlainFormulaBitForBit) {
  Vector x = NewVector(), w = NewVector();
  double sum = 0.0;
  for (int i = 0; i < n(); ++i) {
    const double p = Data(x.get())[i] * Data(w.get())[i];
    sum += p * p;
  }
  EXPECT_EQ(N_VWrmsNorm(x.get(), w.get()), std::sqrt(sum / n()));
}

// Appended quadratures (trailing states with zero weight) take no part in the norm: it is
// that of the leading states alone, bit for bit, the divisor included. InstallErrorNorm (the
// ARKODE vectors, which keep SUNDIALS' other operations) gives the same.
TEST_P(FastSerialOpsTest, WrmsNormLeavesOutTrailingZeroWeights) {
  Vector x = NewVector(), w = NewVector();
  const int controlled = n() - 2;
  Data(w.get())[n() - 1] = Data(w.get())[n() - 2] = 0.0;
  Data(x.get())[n() - 1] = 1e30;  // a quadrature's value: never seen
  double sum = 0.0;
  for (int i = 0; i < controlled; ++i) {
    const double p = Data(x.get())[i] * Data(w.get())[i];
    sum += p * p;
  }
  const double expected = std::sqrt(sum / controlled);
  EXPECT_EQ(N_VWrmsNorm(x.get(), w.get()), expected);
  EXPECT_EQ(ErrorControlledLength(n(), Data(w.get())), controlled);

  Vector plain(N_VNew_Serial(n(), context_.get()));
  Vector plain_w(N_VNew_Serial(n(), context_.get()));
  std::copy(Data(x.get()), Data(x.get()) + n(), Data(plain.get()));
  std::copy(Data(w.get()), Data(w.get()) + n(), Data(plain_w.get()));
  EXPECT_NE(N_VWrmsNorm(plain.get(), plain_w.get()), expected);  // SUNDIALS' divides by n
  InstallErrorNorm(plain.get());
  EXPECT_EQ(N_VWrmsNorm(plain.get(), plain_w.get()), expected);
  // and without zero weights, SUNDIALS' own norm, bit for bit
  Vector leading(N_VNew_Serial(controlled, context_.get()));
  Vector leading_w(N_VNew_Serial(controlled, context_.get()));
  std::copy(Data(x.get()), Data(x.get()) + controlled, Data(leading.get()));
  std::copy(Data(w.get()), Data(w.get()) + controlled, Data(leading_w.get()));
  EXPECT_EQ(N_VWrmsNorm(leading.get(), leading_w.get()), expected);
}

INSTANTIATE_TEST_SUITE_P(Lengths, FastSerialOpsTest, ::testing::Values(12, 13, 7, 14),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return "n" + std::to_string(info.param);
                         });

}  // namespace
}  // namespace mbstream::sundials
