// The body DAE: its declared sparsity holds every non-zero of the iteration matrix, the
// coloured finite differences reproduce the dense ones, and the consistent initial state
// zeroes the residual.
#include "server/body/body_dae.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <set>

#include "server/body/body_cuts.h"
#include "server/body/consistent_init.h"
#include "server/integrate/ida_colored_jacobian.h"
#include "tests/common/test_models.h"
#include "tests/server/body/body_test_util.h"

namespace mbstream {
namespace {

struct Case {
  const char* scene;
  ConstraintLevel level;
};

class BodyDaeTest : public ::testing::TestWithParam<Case> {};

// Every non-zero of a dense finite-difference iteration matrix at a random state lies in
// the declared pattern, and the coloured differences reproduce the dense ones.
// Returns the number of colours.
int ExpectPatternHolds(BodyDae& dae, const BodyModel& bm, const char* label) {
  const int size = dae.size();
  std::set<std::pair<int, int>> pattern;
  const auto& starts = dae.JacobianColumnStarts();
  const auto& rows = dae.JacobianRowIndices();
  for (int j = 0; j < size; ++j) {
    for (int k = starts[j]; k < starts[j + 1]; ++k) pattern.insert({rows[k], j});
  }
  std::mt19937 rng(11);
  const Eigen::VectorXd y = testing::RandomBodyState(bm, rng);
  Eigen::VectorXd yp = testing::RandomBodyState(bm, rng);
  Eigen::VectorXd r0(size), r1(size);
  const double t = 0.7, cj = 3.0;
  EXPECT_EQ(dae.Residual(t, y.data(), yp.data(), r0.data()), 0);
  Eigen::MatrixXd dense(size, size);
  for (int j = 0; j < size; ++j) {
    Eigen::VectorXd ys = y, yps = yp;
    const double h = 1e-7;
    ys(j) += h;
    yps(j) += cj * h;
    EXPECT_EQ(dae.Residual(t, ys.data(), yps.data(), r1.data()), 0);
    dense.col(j) = (r1 - r0) / h;
    for (int i = 0; i < size; ++i) {
      if (std::abs(dense(i, j)) > 1e-6 * (1.0 + std::abs(r0(i)))) {
        EXPECT_TRUE(pattern.count({i, j})) << "non-zero outside the pattern at row " << i
                                           << ", column " << j << ": " << dense(i, j);
      }
    }
  }
  // Coloured differences give the same matrix.
  ColoredJacobian colored(dae);
  EXPECT_LT(colored.num_colors(), size);
  std::printf("%s: %d unknowns, %d non-zeros, %d colours\n", label, size, dae.JacobianNonZeros(),
              colored.num_colors());
  std::vector<double> values(rows.size());
  const Eigen::VectorXd ewt = Eigen::VectorXd::Constant(size, 1e7);
  EXPECT_EQ(
      colored.Evaluate(t, cj, 1e-3, y.data(), yp.data(), r0.data(), ewt.data(), values.data()), 0);
  for (int j = 0; j < size; ++j) {
    for (int k = starts[j]; k < starts[j + 1]; ++k) {
      EXPECT_NEAR(values[k], dense(rows[k], j), 1e-4 * (1.0 + std::abs(dense(rows[k], j))))
          << rows[k] << ", " << j;
    }
  }
  return colored.num_colors();
}

TEST_P(BodyDaeTest, PatternHoldsEveryNonZero) {
  const Model& model = testing::Irb1600();
  RunConfig config = testing::Scene(GetParam().scene);
  const DriveSet drives(model, config.drives);
  const BodyModel bm = MakeBodyModel(model, drives, Eigen::VectorXd());
  BodyDae dae(bm, drives, GetParam().level);
  const std::string label =
      std::string(GetParam().scene) + ", " +
      (GetParam().level == ConstraintLevel::kPosition ? "index 3" : "index 2");
  // A chain couples each body to two neighbours only: far fewer colours than columns.
  EXPECT_LT(ExpectPatternHolds(dae, bm, label.c_str()), dae.size() / 2);
}

TEST_P(BodyDaeTest, ConsistentInitialStateZeroesTheResidual) {
  const Model& model = testing::Irb1600();
  const RunConfig config = testing::Scene(GetParam().scene);
  const DriveSet drives(model, config.drives);
  Eigen::VectorXd q0(6), qd0(6);
  for (int i = 0; i < 6; ++i) {
    q0(i) = drives.prescribed(i) ? drives.Reference(i, 0.0).q : 0.1 * i;
    qd0(i) = drives.prescribed(i) ? drives.Reference(i, 0.0).qd : 0.2 - 0.1 * i;
  }
  const BodyModel bm = MakeBodyModel(model, drives, q0);
  BodyDae dae(bm, drives, GetParam().level);
  BodyInitialState init;
  ASSERT_TRUE(ConsistentInitialState(model, bm, dae.mechanics(), 0.0, q0, qd0, &init));
  Eigen::VectorXd r(dae.size());
  ASSERT_EQ(dae.Residual(0.0, init.y.data(), init.yp.data(), r.data()), 0);
  EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-9);
}

TEST(BodyDaeBranchingTest, PatternHoldsEveryNonZeroWithPrismaticJoints) {
  const Model model = testing::BranchingModel();
  for (bool prescribed : {true, false}) {
    const RunConfig config = testing::BranchingDrives(model, prescribed);
    const DriveSet drives(model, config.drives);
    const BodyModel bm = MakeBodyModel(model, drives, Eigen::VectorXd());
    for (ConstraintLevel level : {ConstraintLevel::kPosition, ConstraintLevel::kVelocity}) {
      BodyDae dae(bm, drives, level);
      ExpectPatternHolds(dae, bm, "branching");
    }
  }
}

TEST(BodyDaeBranchingTest, PatternHoldsEveryNonZeroWithCutJoints) {
  const Model model = testing::BranchingModel();
  const RunConfig config = testing::BranchingDrives(model, /*all_prescribed=*/false);
  const DriveSet drives(model, config.drives);
  BodyModel bm = MakeBodyModel(model, drives, Eigen::VectorXd());
  AddCutJoints(testing::CutsOfEveryKind(), &bm);  // every row kept
  for (ConstraintLevel level : {ConstraintLevel::kPosition, ConstraintLevel::kVelocity}) {
    BodyDae dae(bm, drives, level);
    ExpectPatternHolds(dae, bm, "branching with cut joints");
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, BodyDaeTest,
                         ::testing::Values(Case{"seed-run", ConstraintLevel::kPosition},
                                           Case{"seed-run", ConstraintLevel::kVelocity},
                                           Case{"seed-servo", ConstraintLevel::kPosition},
                                           Case{"seed-servo", ConstraintLevel::kVelocity}));

}  // namespace
}  // namespace mbstream
