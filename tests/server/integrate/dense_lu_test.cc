// The panel-blocked LU of big blocks (dense_lu.h, LuFactorBlocked) gives the column-by-column
// LU's factors and pivots bit for bit, zero multipliers and row swaps included, and solves.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <vector>

#include "server/integrate/dense_lu.h"

namespace mbstream::sundials {
namespace {

// A random n x n matrix (leading dimension ld >= n) with a fraction of exact zeros, so that
// the zero-multiplier skips are exercised, and small diagonals, so that rows are swapped.
std::vector<double> RandomBlock(int n, int ld, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  std::vector<double> a(static_cast<size_t>(ld) * n, 7.0);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = dist(rng);
      a[j * ld + i] = std::abs(x) < 0.3 ? 0.0 : (i == j ? 0.01 * x : x);
    }
  }
  return a;
}

template <int kN>
void ExpectBlockedEqualsColumnByColumn(int ld) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    std::vector<double> reference = RandomBlock(kN, ld, seed), blocked = reference;
    std::vector<sunindextype> reference_pivots(kN), blocked_pivots(kN);
    // Fixed<kN>: the column-by-column loops; a run-time size >= kLuBlockMin: the panels.
    ASSERT_EQ(LuFactor(Fixed<kN>(), ld, reference.data(), reference_pivots.data()), 0);
    ASSERT_EQ(LuFactor(sunindextype{kN}, ld, blocked.data(), blocked_pivots.data()), 0);
    EXPECT_EQ(blocked_pivots, reference_pivots) << "seed " << seed;
    EXPECT_EQ(blocked, reference) << "seed " << seed;  // bit for bit, padding untouched
  }
}

TEST(DenseLuTest, BlockedLuEqualsColumnByColumnBitForBit) {
  static_assert(kLuBlockMin <= 24);
  ExpectBlockedEqualsColumnByColumn<24>(24);
  ExpectBlockedEqualsColumnByColumn<41>(41);    // a partial last panel
  ExpectBlockedEqualsColumnByColumn<100>(130);  // a block inside a larger matrix
}

TEST(DenseLuTest, BlockedLuFactorsSolveTheSystem) {
  const int n = 150;
  std::vector<double> a = RandomBlock(n, n, 9);
  const Eigen::MatrixXd m = Eigen::Map<Eigen::MatrixXd>(a.data(), n, n);
  std::vector<sunindextype> pivots(n);
  ASSERT_EQ(LuFactor(sunindextype{n}, sunindextype{n}, a.data(), pivots.data()), 0);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  Eigen::VectorXd x = b;
  LuSubstitute(sunindextype{n}, sunindextype{n}, a.data(), pivots.data(), x.data());
  EXPECT_LT((m * x - b).norm(), 1e-9 * b.norm());
}

TEST(DenseLuTest, BlockedLuReportsTheFirstZeroPivotAsColumnByColumnDoes) {
  const int n = 40;
  std::vector<double> a = RandomBlock(n, n, 3);
  for (int i = 0; i < n; ++i) a[29 * n + i] = 0.0;  // column 29 stays exactly zero
  std::vector<double> reference = a;
  std::vector<sunindextype> pivots(n);
  EXPECT_EQ(LuFactor(sunindextype{n}, sunindextype{n}, a.data(), pivots.data()), 30);
  EXPECT_EQ(LuFactor(Fixed<40>(), Fixed<40>(), reference.data(), pivots.data()), 30);
}

}  // namespace
}  // namespace mbstream::sundials
