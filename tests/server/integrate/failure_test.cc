// Failures: each ends with a clear status and message, a finite last good state, and t at
// the last good time.
#include <cmath>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "server/integrate/ida_integrator.h"
#include "server/integrate/integrator.h"
#include "tests/server/integrate/test_systems.h"

namespace mbstream {
namespace {

using testing::ExponentialGrowth;
using testing::FailingOscillator;
using testing::HarmonicOscillator;
using testing::NanOscillator;
using testing::Options;
using testing::OscillatorDae;

constexpr Method kAllMethods[] = {Method::kBdf,  Method::kAdams, Method::kErk,
                                  Method::kDirk, Method::kRk4,   Method::kEuler};

// Advances over [0, t_final] in outputs of 0.1 s until a failure; returns it.
AdvanceResult RunUntilFailure(Integrator& integrator, double t_final, double* y) {
  AdvanceResult result;
  for (int k = 1; k * 0.1 <= t_final + 1e-12; ++k) {
    result = integrator.AdvanceTo(std::min(k * 0.1, t_final), y);
    if (result.status != IntegratorStatus::kOk) break;
  }
  return result;
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(FailureTest, UnrecoverableRhsFailureStopsEveryMethod) {
  for (Method method : kAllMethods) {
    FailingOscillator system(/*t_fail=*/0.5, /*code=*/-7);
    const double y0[2] = {1.0, 0.0};
    IntegratorOptions options = Options(method, 2.0);
    options.fixed_step = 0.01;
    auto integrator = MakeIntegrator(system, 0.0, y0, options);
    double y[2];
    const AdvanceResult result = RunUntilFailure(*integrator, 2.0, y);
    ASSERT_EQ(result.status, IntegratorStatus::kRhsFailure) << integrator->name();
    EXPECT_TRUE(Contains(result.message, "code -7")) << result.message;
    EXPECT_TRUE(Contains(result.message, "check the model")) << result.message;
    // The last good time: the solver's last step before a stage reached t = 0.5 s.
    EXPECT_LE(result.t, 0.5);
    EXPECT_GE(result.t, 0.2);
    // The last good state is the oscillator's, at the last good time.
    const double tolerance = method == Method::kEuler ? 1e-2 : 1e-4;  // Euler: first order
    EXPECT_NEAR(y[0], std::cos(result.t), tolerance) << integrator->name();
    EXPECT_NEAR(y[1], -std::sin(result.t), tolerance) << integrator->name();
  }
}

TEST(FailureTest, PersistentRecoverableFailureIsReported) {
  // A model that cannot be evaluated even at the initial state.
  for (Method method : {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk}) {
    FailingOscillator system(/*t_fail=*/0.0, /*code=*/3);
    const double y0[2] = {1.0, 0.0};
    auto integrator = MakeIntegrator(system, 0.0, y0, Options(method, 2.0));
    double y[2];
    const AdvanceResult result = integrator->AdvanceTo(0.1, y);
    EXPECT_EQ(result.status, IntegratorStatus::kRhsFailure)
        << integrator->name() << ": " << result.message;
    EXPECT_TRUE(Contains(result.message, "code 3")) << result.message;
    EXPECT_EQ(result.t, 0.0);
    EXPECT_EQ(y[0], 1.0);
    EXPECT_EQ(y[1], 0.0);
  }
}

TEST(FailureTest, FixedStepMethodsCannotRetryARecoverableFailure) {
  FailingOscillator system(/*t_fail=*/0.5, /*code=*/3);
  const double y0[2] = {1.0, 0.0};
  IntegratorOptions options = Options(Method::kRk4, 2.0);
  options.fixed_step = 0.01;
  auto rk4 = MakeIntegrator(system, 0.0, y0, options);
  double y[2];
  const AdvanceResult result = RunUntilFailure(*rk4, 2.0, y);
  EXPECT_EQ(result.status, IntegratorStatus::kRhsFailure);
  EXPECT_TRUE(Contains(result.message, "cannot retry")) << result.message;
  EXPECT_NEAR(result.t, 0.49, 1e-9);
  EXPECT_NEAR(y[0], std::cos(0.49), 1e-8);
}

TEST(FailureTest, NonFiniteDerivativeIsARhsFailure) {
  for (Method method : kAllMethods) {
    NanOscillator system(0.5);
    const double y0[2] = {1.0, 0.0};
    auto integrator = MakeIntegrator(system, 0.0, y0, Options(method, 2.0));
    double y[2];
    const AdvanceResult result = RunUntilFailure(*integrator, 2.0, y);
    ASSERT_EQ(result.status, IntegratorStatus::kRhsFailure) << integrator->name();
    EXPECT_TRUE(Contains(result.message, "non-finite derivative")) << result.message;
    EXPECT_TRUE(std::isfinite(y[0]) && std::isfinite(y[1]));
    EXPECT_LE(result.t, 0.5);
  }
}

TEST(FailureTest, AdaptiveMethodsReportDivergence) {
  // y' = y from 1 passes 1e10 at t = ln(1e10) = 23.03 s.
  for (Method method : {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk}) {
    ExponentialGrowth system;
    const double y0[1] = {1.0};
    auto integrator = MakeIntegrator(system, 0.0, y0, Options(method, 30.0));
    double y[1];
    const AdvanceResult result = RunUntilFailure(*integrator, 30.0, y);
    ASSERT_EQ(result.status, IntegratorStatus::kDiverged) << integrator->name();
    EXPECT_GT(result.t, 22.0);
    EXPECT_LT(result.t, 23.1);
    EXPECT_TRUE(std::isfinite(y[0]));
    EXPECT_LE(y[0], 1e10);
    EXPECT_NEAR(y[0], std::exp(result.t), 1e-4 * std::exp(result.t)) << integrator->name();
    EXPECT_TRUE(Contains(result.message, "exceeded 1e+10")) << result.message;
  }
}

TEST(FailureTest, MaxStepsIsATotalBudget) {
  for (Method method : {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk, Method::kRk4}) {
    HarmonicOscillator system(2.0 * M_PI);
    const double y0[2] = {1.0, 0.0};
    IntegratorOptions options = Options(method, 10.0);
    options.max_steps = 50;
    options.fixed_step = 0.01;
    auto integrator = MakeIntegrator(system, 0.0, y0, options);
    double y[2];
    const AdvanceResult result = RunUntilFailure(*integrator, 10.0, y);
    ASSERT_EQ(result.status, IntegratorStatus::kTooMuchWork) << integrator->name();
    EXPECT_TRUE(Contains(result.message, "max_steps = 50")) << result.message;
    EXPECT_LE(integrator->stats().steps, 50) << integrator->name();
    EXPECT_GT(result.t, 0.0);
    EXPECT_LT(result.t, 10.0);
    EXPECT_NEAR(y[0], system.Position(result.t, 1.0, 0.0), 1e-3) << integrator->name();
  }
  // The explicit method suggests an implicit one.
  HarmonicOscillator system(1.0);
  const double y0[2] = {1.0, 0.0};
  IntegratorOptions options = Options(Method::kErk, 10.0);
  options.max_steps = 5;
  auto erk = MakeIntegrator(system, 0.0, y0, options);
  double y[2];
  const AdvanceResult result = RunUntilFailure(*erk, 10.0, y);
  EXPECT_TRUE(Contains(result.message, "try method bdf or dirk")) << result.message;
}

// The step budget runs out only where a step is needed: an output within the last internal
// step is interpolated, whatever the budget, by every adaptive method, IDA's included.
TEST(FailureTest, AnOutputWithinTheLastStepNeedsNoStepBudget) {
  HarmonicOscillator ode(1.0);
  OscillatorDae dae;
  const double y0[2] = {1.0, 0.0}, yp0[2] = {0.0, -1.0};
  auto make = [&](Method method, long max_steps) -> std::unique_ptr<Integrator> {
    IntegratorOptions options = Options(method, 2.0);
    options.max_steps = max_steps;
    if (method != Method::kIda) return MakeIntegrator(ode, 0.0, y0, options);
    IdaOptions ida;
    ida.base = options;
    return MakeIdaIntegrator(dae, 0.0, y0, yp0, ida);
  };
  for (Method method : {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk, Method::kIda}) {
    // How many steps reach t = 1 s, and an output past it that needs no further step.
    auto free = make(method, 100'000);
    double y_free[2], y[2];
    ASSERT_EQ(free->AdvanceTo(1.0, y_free).status, IntegratorStatus::kOk) << free->name();
    const long steps = free->stats().steps;
    const double t2 = 1.0 + 1e-9;
    ASSERT_EQ(free->AdvanceTo(t2, y_free).status, IntegratorStatus::kOk);
    ASSERT_EQ(free->stats().steps, steps) << free->name() << ": t2 needed another step";

    auto budgeted = make(method, steps);
    EXPECT_EQ(budgeted->AdvanceTo(1.0, y).status, IntegratorStatus::kOk) << budgeted->name();
    const AdvanceResult within = budgeted->AdvanceTo(t2, y);
    EXPECT_EQ(within.status, IntegratorStatus::kOk) << budgeted->name() << ": " << within.message;
    EXPECT_DOUBLE_EQ(y[0], y_free[0]) << budgeted->name();
    const AdvanceResult beyond = budgeted->AdvanceTo(1.5, y);
    EXPECT_EQ(beyond.status, IntegratorStatus::kTooMuchWork) << budgeted->name();
    EXPECT_EQ(budgeted->stats().steps, steps) << budgeted->name();
  }
}

TEST(FailureTest, SundialsStaysQuiet) {
  ::testing::internal::CaptureStderr();
  FailingOscillator system(0.5, -7);
  const double y0[2] = {1.0, 0.0};
  for (Method method : {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk}) {
    auto integrator = MakeIntegrator(system, 0.0, y0, Options(method, 2.0));
    double y[2];
    RunUntilFailure(*integrator, 2.0, y);
    integrator->stats();
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

}  // namespace
}  // namespace mbstream
