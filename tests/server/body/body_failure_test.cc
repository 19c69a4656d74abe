// Where the body formulations fail, measured: index 3 with IDA at tight tolerances, and
// Baumgarte stabilisation with bad parameters (none: drift; too strong: stiffness).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "server/engine/engine.h"
#include "tests/server/body/body_test_util.h"

namespace mbstream {
namespace {

bool AllFinite(const std::vector<double>& values) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

class BodyIndex3TightTest : public ::testing::TestWithParam<double> {};

TEST_P(BodyIndex3TightTest, FailsFastWithAdviceAndFiniteFrames) {
  const double rtol = GetParam();
  RunConfig config = testing::SeedRun(Formulation::kBodyIndex3, Method::kIda, rtol);
  config.want_torques = true;
  const auto start = std::chrono::steady_clock::now();
  const RunResult result = Simulate(testing::Irb1600(), config);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const RunStats& s = result.stats;
  std::printf(
      "body-index3 rtol %.0e: %s after %ld steps, %ld error-test and %ld convergence "
      "failures, t reached %.3g s, %.3g s wall\n  %s\n",
      rtol, RunStatusName(s.status), s.solver.steps, s.solver.error_test_failures,
      s.solver.convergence_failures, s.t_reached, wall, s.message.c_str());
  EXPECT_TRUE(s.status == RunStatus::kConvergenceFailures ||
              s.status == RunStatus::kErrorTestFailures || s.status == RunStatus::kTooMuchWork)
      << RunStatusName(s.status);
  EXPECT_LT(s.t_reached, config.duration);
  EXPECT_NE(s.message.find("body-index2"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("body-baumgarte"), std::string::npos) << s.message;
  // Fast in work, not wall time (machine-dependent; timing belongs in bench/): it fails
  // within a few dozen steps (24 at rtol 1e-6), not at the end of a step budget.
  EXPECT_LT(s.solver.steps, 1000);
  EXPECT_GE(result.num_frames(), 1);
  EXPECT_TRUE(AllFinite(result.q) && AllFinite(result.qd) && AllFinite(result.tcp) &&
              AllFinite(result.tau));
}

INSTANTIATE_TEST_SUITE_P(Tolerances, BodyIndex3TightTest, ::testing::Values(1e-6, 1e-8, 1e-10));

// At a loose tolerance index 3 does get through, but the velocities (index-2 variables) fail
// the error test at almost every step: under a step budget it runs out of work.
TEST(BodyIndex3Test, LooseToleranceCollapsesTheStepUnderABudget) {
  RunConfig config = testing::SeedRun(Formulation::kBodyIndex3, Method::kIda, 1e-4);
  config.max_steps = 3000;
  const RunResult result = Simulate(testing::Irb1600(), config);
  const RunStats& s = result.stats;
  std::printf(
      "body-index3 rtol 1e-4, 3000 steps: %s at t = %.3g s, %ld error-test failures, "
      "last step %.3g s\n",
      RunStatusName(s.status), s.t_reached, s.solver.error_test_failures, s.solver.last_step);
  EXPECT_EQ(s.status, RunStatus::kTooMuchWork);
  EXPECT_GT(s.solver.error_test_failures, s.solver.steps / 2);
  EXPECT_LT(s.t_reached, 5.0);  // index 2 needs about 400 steps for the whole 20 s
  EXPECT_NE(s.message.find("body-index2"), std::string::npos);
}

RunConfig Baumgarte(double alpha, double beta, Method method, double duration) {
  RunConfig config = testing::SeedRun(Formulation::kBodyBaumgarte, method, 1e-6);
  config.baumgarte = {alpha, beta};
  config.duration = duration;
  return config;
}

TEST(BodyBaumgarteTest, WithoutStabilisationTheConstraintsDrift) {
  const RunResult good = Simulate(testing::Irb1600(), Baumgarte(10, 25, Method::kBdf, 20));
  const RunResult none = Simulate(testing::Irb1600(), Baumgarte(0, 0, Method::kBdf, 20));
  ASSERT_EQ(good.stats.status, RunStatus::kFinished);
  ASSERT_EQ(none.stats.status, RunStatus::kFinished);
  std::printf(
      "baumgarte rtol 1e-6: alpha 10, beta 25: drift %.3g m, TCP error %.3g m; "
      "alpha = beta = 0: drift %.3g m, TCP error %.3g m\n",
      good.stats.drift_position_max, good.stats.tcp_error_max, none.stats.drift_position_max,
      none.stats.tcp_error_max);
  EXPECT_GT(none.stats.drift_position_max, 30 * good.stats.drift_position_max);
  EXPECT_GT(none.stats.tcp_error_max, 10 * 1e-6);  // beyond the 10 x rtol bound
  EXPECT_LE(good.stats.tcp_error_max, 10 * 1e-6);
}

TEST(BodyBaumgarteTest, StrongStabilisationMakesTheSystemStiff) {
  // alpha = 2 sqrt(beta) (critically damped) at 1000 1/s instead of 5 1/s: eigenvalues near
  // -1000 1/s that an explicit method must resolve by stability.
  const RunResult good = Simulate(testing::Irb1600(), Baumgarte(10, 25, Method::kErk, 2));
  const RunResult stiff = Simulate(testing::Irb1600(), Baumgarte(2000, 1e6, Method::kErk, 2));
  ASSERT_EQ(good.stats.status, RunStatus::kFinished);
  ASSERT_EQ(stiff.stats.status, RunStatus::kFinished);
  std::printf(
      "baumgarte erk rtol 1e-6, 2 s: alpha 10, beta 25: %ld steps; alpha 2000, beta "
      "1e6: %ld steps\n",
      good.stats.solver.steps, stiff.stats.solver.steps);
  EXPECT_GT(stiff.stats.solver.steps, 20 * good.stats.solver.steps);
}

}  // namespace
}  // namespace mbstream
