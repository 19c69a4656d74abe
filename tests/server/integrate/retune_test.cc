// Integrator::Retune: an integration goes on with other tolerances and a later stop time,
// keeping its step size and order (a run that continues a pilot, server/sim/run_prefix.h).
#include <cmath>
#include <exception>

#include <gtest/gtest.h>

#include "server/integrate/integrator.h"
#include "tests/server/integrate/test_systems.h"

namespace mbstream {
namespace {

using testing::HarmonicOscillator;
using testing::Options;
using testing::StiffRelaxation;

constexpr double kPilotEnd = 0.5;  // s
constexpr double kEnd = 10.0;      // s

struct Leg {
  long steps = 0;  // steps taken over [kPilotEnd, kEnd]
  double max_error = 0.0;
};

// Over [kPilotEnd, kEnd] at `rtol`: the integration retuned after a pilot at `pilot_rtol`
// over [0, kPilotEnd], or (retune false) a fresh one from the exact state at kPilotEnd.
Leg RunStiffLeg(Method method, double pilot_rtol, double rtol, bool retune) {
  StiffRelaxation system(1000.0);
  double y[1] = {1.0};
  std::unique_ptr<Integrator> integrator;
  if (retune) {
    integrator = MakeIntegrator(system, 0.0, y, Options(method, kPilotEnd, pilot_rtol));
    EXPECT_EQ(integrator->AdvanceTo(kPilotEnd, y).status, IntegratorStatus::kOk);
    EXPECT_TRUE(integrator->Retune(Options(method, kEnd, rtol)));
  } else {
    y[0] = system.Exact(kPilotEnd);
    integrator = MakeIntegrator(system, kPilotEnd, y, Options(method, kEnd, rtol));
  }
  const long before = integrator->stats().steps;
  Leg leg;
  for (int k = 1; k <= 95; ++k) {
    const double t = kPilotEnd + 0.1 * k;
    const AdvanceResult result = integrator->AdvanceTo(t, y);
    EXPECT_EQ(result.status, IntegratorStatus::kOk) << result.message;
    leg.max_error = std::max(leg.max_error, std::abs(y[0] - system.Exact(t)));
  }
  leg.steps = integrator->stats().steps - before;
  return leg;
}

TEST(RetuneTest, BdfGoesOnWithoutStartingAgain) {
  const Leg continued = RunStiffLeg(Method::kBdf, 1e-10, 1e-6, true);
  const Leg fresh = RunStiffLeg(Method::kBdf, 1e-10, 1e-6, false);
  // A fresh start takes dozens of steps at order 1 to grow its step; the retuned integration
  // goes on at its order and grows its step at once.
  EXPECT_LT(continued.steps, fresh.steps) << continued.steps << " vs " << fresh.steps;
  // The looser tolerance is in force: fewer steps than the pilot's tolerance would take.
  const Leg tight = RunStiffLeg(Method::kBdf, 1e-10, 1e-10, true);
  EXPECT_LT(3 * continued.steps, tight.steps) << continued.steps << " vs " << tight.steps;
  EXPECT_LT(continued.max_error, 1e-5);
  EXPECT_LT(tight.max_error, 1e-8);
}

TEST(RetuneTest, EveryAdaptiveMethodGoesOnAccurately) {
  for (Method method : {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk}) {
    HarmonicOscillator system(2.0, /*with_jacobian=*/true);
    double y[2] = {1.0, 0.0};
    auto integrator = MakeIntegrator(system, 0.0, y, Options(method, 1.0, 1e-4));
    ASSERT_EQ(integrator->AdvanceTo(1.0, y).status, IntegratorStatus::kOk);
    ASSERT_TRUE(integrator->Retune(Options(method, 5.0, 1e-9))) << MethodName(method);
    ASSERT_EQ(integrator->AdvanceTo(5.0, y).status, IntegratorStatus::kOk);
    // The pilot's error at t = 1 (about 1e-4) is carried on, not made smaller: the check is
    // that the integration reached t = 5 on the right track, with the new stop time.
    EXPECT_NEAR(y[0], system.Position(5.0, 1.0, 0.0), 1e-3) << MethodName(method);
    EXPECT_NEAR(y[1], system.Velocity(5.0, 1.0, 0.0), 2e-3) << MethodName(method);
    EXPECT_LE(system.max_time_seen, 5.0 + 1e-9) << MethodName(method);
  }
}

TEST(RetuneTest, RefusesWhatItCannotContinue) {
  HarmonicOscillator system(2.0);
  double y[2] = {1.0, 0.0};
  auto bdf = MakeIntegrator(system, 0.0, y, Options(Method::kBdf, 1.0));
  ASSERT_EQ(bdf->AdvanceTo(1.0, y).status, IntegratorStatus::kOk);
  EXPECT_FALSE(bdf->Retune(Options(Method::kAdams, 2.0)));  // another method
  EXPECT_FALSE(bdf->Retune(Options(Method::kBdf, 0.5)));    // stop time before t = 1
  IntegratorOptions no_rtol = Options(Method::kBdf, 2.0);
  no_rtol.rtol = 0.0;
  EXPECT_FALSE(bdf->Retune(no_rtol));
  // Refused retunes change nothing: the stop time is still t = 1.
  EXPECT_EQ(bdf->AdvanceTo(1.0, y).status, IntegratorStatus::kOk);
  EXPECT_THROW(bdf->AdvanceTo(1.5, y), std::exception);
  auto rk4 = MakeIntegrator(system, 0.0, y, Options(Method::kRk4, 1.0));
  EXPECT_FALSE(rk4->Retune(Options(Method::kRk4, 2.0)));  // fixed step: nothing to keep
}

TEST(RetuneTest, TheStepBudgetCountsFromTheRetune) {
  StiffRelaxation system(1000.0);
  double y[1] = {1.0};
  auto integrator = MakeIntegrator(system, 0.0, y, Options(Method::kBdf, kPilotEnd, 1e-8));
  ASSERT_EQ(integrator->AdvanceTo(kPilotEnd, y).status, IntegratorStatus::kOk);
  const long pilot_steps = integrator->stats().steps;
  ASSERT_GT(pilot_steps, 5);
  IntegratorOptions options = Options(Method::kBdf, kEnd, 1e-8);
  options.max_steps = 5;
  ASSERT_TRUE(integrator->Retune(options));
  const AdvanceResult result = integrator->AdvanceTo(kEnd, y);
  EXPECT_EQ(result.status, IntegratorStatus::kTooMuchWork);
  EXPECT_EQ(integrator->stats().steps, pilot_steps + 5);
}

}  // namespace
}  // namespace mbstream
