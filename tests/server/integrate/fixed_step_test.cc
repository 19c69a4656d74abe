// Fixed-step RK4 and semi-implicit Euler: convergence order, the landing rule, stability.
#include <cmath>

#include <gtest/gtest.h>

#include "server/integrate/integrator.h"
#include "tests/server/integrate/test_systems.h"

namespace mbstream {
namespace {

using testing::HarmonicOscillator;
using testing::Options;
using testing::StiffRelaxation;

// The error at t = 0.8 s (not a whole period, where errors can cancel) of an oscillator with
// period 1 s, step h: the larger of the position error and the velocity error / omega.
double FinalError(Method method, double h) {
  constexpr double kOmega = 2.0 * M_PI;
  constexpr double kFinal = 0.8;
  HarmonicOscillator system(kOmega);
  const double y0[2] = {1.0, 0.0};
  IntegratorOptions options = Options(method, kFinal);
  options.fixed_step = h;
  auto integrator = MakeIntegrator(system, 0.0, y0, options);
  double y[2];
  const AdvanceResult result = integrator->AdvanceTo(kFinal, y);
  EXPECT_EQ(result.status, IntegratorStatus::kOk) << result.message;
  return std::max(std::abs(y[0] - system.Position(kFinal, y0[0], y0[1])),
                  std::abs(y[1] - system.Velocity(kFinal, y0[0], y0[1])) / kOmega);
}

TEST(FixedStepTest, Rk4IsFourthOrder) {
  const double coarse = FinalError(Method::kRk4, 0.01);
  const double fine = FinalError(Method::kRk4, 0.005);
  EXPECT_GT(coarse / fine, 14.0);
  EXPECT_LT(coarse / fine, 18.0);
  EXPECT_LT(fine, 1e-5);
}

TEST(FixedStepTest, SemiImplicitEulerIsFirstOrder) {
  const double coarse = FinalError(Method::kEuler, 0.002);
  const double fine = FinalError(Method::kEuler, 0.001);
  EXPECT_GT(coarse / fine, 1.8);
  EXPECT_LT(coarse / fine, 2.2);
}

TEST(FixedStepTest, SemiImplicitEulerKeepsTheEnergyBounded) {
  // Symplectic: over 100 periods the energy oscillates but does not drift.
  HarmonicOscillator system(2.0 * M_PI);
  const double y0[2] = {1.0, 0.0};
  IntegratorOptions options = Options(Method::kEuler, 100.0);
  options.fixed_step = 0.01;
  auto integrator = MakeIntegrator(system, 0.0, y0, options);
  const double w2 = 4.0 * M_PI * M_PI;
  const double e0 = 0.5 * w2;
  double y[2];
  for (int k = 1; k <= 100; ++k) {
    ASSERT_EQ(integrator->AdvanceTo(k, y).status, IntegratorStatus::kOk);
    const double energy = 0.5 * y[1] * y[1] + 0.5 * w2 * y[0] * y[0];
    EXPECT_NEAR(energy / e0, 1.0, 0.35);
  }
}

TEST(FixedStepTest, OutputsDoNotPerturbTheGrid) {
  // The state on a grid point is the same whether or not outputs fell in between.
  for (Method method : {Method::kRk4, Method::kEuler}) {
    IntegratorOptions options = Options(method, 1.0);
    options.fixed_step = 0.003;
    const double y0[2] = {1.0, 0.0};
    HarmonicOscillator direct_system(2.0 * M_PI), busy_system(2.0 * M_PI);
    auto direct = MakeIntegrator(direct_system, 0.0, y0, options);
    auto busy = MakeIntegrator(busy_system, 0.0, y0, options);
    double y_direct[2], y_busy[2];
    const double t_grid = 0.003 * 100;
    ASSERT_EQ(direct->AdvanceTo(t_grid, y_direct).status, IntegratorStatus::kOk);
    for (int k = 1; k <= 29; ++k) {
      ASSERT_EQ(busy->AdvanceTo(0.01 * k, y_busy).status, IntegratorStatus::kOk);
    }
    ASSERT_EQ(busy->AdvanceTo(t_grid, y_busy).status, IntegratorStatus::kOk);
    EXPECT_EQ(y_direct[0], y_busy[0]) << direct->name();
    EXPECT_EQ(y_direct[1], y_busy[1]) << direct->name();
    EXPECT_EQ(direct->stats().steps, 100);
    EXPECT_EQ(busy->stats().steps, 100);
  }
}

TEST(FixedStepTest, StatisticsCountStepsAndEvaluations) {
  HarmonicOscillator system(1.0);
  const double y0[2] = {1.0, 0.0};
  IntegratorOptions options = Options(Method::kRk4, 1.0);
  options.fixed_step = 0.01;
  auto rk4 = MakeIntegrator(system, 0.0, y0, options);
  double y[2];
  ASSERT_EQ(rk4->AdvanceTo(1.0, y).status, IntegratorStatus::kOk);
  SolverStats stats = rk4->stats();
  EXPECT_EQ(stats.steps, 100);
  EXPECT_EQ(stats.rhs_evals, 400);
  EXPECT_NEAR(stats.last_step, 0.01, 1e-15);
  EXPECT_EQ(stats.last_order, 4);
  EXPECT_EQ(stats.jac_evals, 0);

  options.method = Method::kEuler;
  auto euler = MakeIntegrator(system, 0.0, y0, options);
  ASSERT_EQ(euler->AdvanceTo(1.0, y).status, IntegratorStatus::kOk);
  stats = euler->stats();
  EXPECT_EQ(stats.steps, 100);
  EXPECT_EQ(stats.rhs_evals, 100);
  EXPECT_EQ(stats.last_order, 1);
}

TEST(FixedStepTest, Rk4BeyondItsStabilityLimitDiverges) {
  // lambda h = 1000 * 0.01 = 10, far outside RK4's stability interval (|lambda h| < 2.79).
  StiffRelaxation system(1000.0);
  const double y0[1] = {1.0};
  IntegratorOptions options = Options(Method::kRk4, 10.0);
  options.fixed_step = 0.01;
  auto integrator = MakeIntegrator(system, 0.0, y0, options);
  double y[1];
  AdvanceResult result;
  int k = 1;
  for (; k <= 200; ++k) {
    result = integrator->AdvanceTo(0.05 * k, y);
    if (result.status != IntegratorStatus::kOk) break;
  }
  ASSERT_EQ(result.status, IntegratorStatus::kDiverged);
  EXPECT_LT(result.t, 10.0);
  EXPECT_GT(result.t, 0.0);
  EXPECT_TRUE(std::isfinite(y[0]));
  EXPECT_LE(std::abs(y[0]), 1e10);
  EXPECT_NE(result.message.find("exceeded 1e+10"), std::string::npos) << result.message;
  EXPECT_NE(result.message.find("--step"), std::string::npos) << result.message;
  EXPECT_NE(result.message.find("bdf"), std::string::npos) << result.message;

  // The failure sticks: a later call returns it again with the same last good state.
  double again[1];
  const AdvanceResult later = integrator->AdvanceTo(10.0, again);
  EXPECT_EQ(later.status, IntegratorStatus::kDiverged);
  EXPECT_EQ(later.t, result.t);
  EXPECT_EQ(again[0], y[0]);
}

TEST(FixedStepTest, Rk4WithinItsStabilityLimitFollowsTheStiffSolution) {
  StiffRelaxation system(1000.0);
  const double y0[1] = {1.0};
  IntegratorOptions options = Options(Method::kRk4, 1.0);
  options.fixed_step = 0.002;  // lambda h = 2
  auto integrator = MakeIntegrator(system, 0.0, y0, options);
  double y[1];
  ASSERT_EQ(integrator->AdvanceTo(1.0, y).status, IntegratorStatus::kOk);
  EXPECT_NEAR(y[0], system.Exact(1.0), 1e-6);
}

}  // namespace
}  // namespace mbstream
