// The energy balance of a driven or damped run: the work W(t) of drives and damping is a
// quadrature of the ODE, so the energy error measures the integrator, not a trapezoid rule
// over the output frames (nor the output interval).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "server/engine/engine.h"
#include "server/integrate/integrator.h"
#include "server/sim/initial_state.h"
#include "server/sim/integrator_options_from.h"
#include "server/sim/joint_space_ode.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream {
namespace {

using testing::Irb1600;
using testing::Scene;

// The IRB 1600 with viscous damping on every joint (N*m*s/rad).
Model DampedIrb1600(double damping) {
  Model model = Irb1600();
  for (Body& body : model.bodies) body.joint.damping = damping;
  return model;
}

// The passive swing, 2 s of it, on the damped arm.
RunConfig DampedSwing(Method method, double rtol) {
  RunConfig config = Scene("passive-swing");
  config.duration = 2.0;
  config.method = method;
  config.rtol = rtol;
  config.atol = rtol / 100;
  return config;
}

TEST(WorkQuadratureTest, DampedArmEnergyErrorIsAtIntegratorLevel) {
  const Model model = DampedIrb1600(5.0);
  for (Method method : {Method::kBdf, Method::kErk}) {
    const RunResult loose = Simulate(model, DampedSwing(method, 1e-6));
    const RunResult tight = Simulate(model, DampedSwing(method, 1e-10));
    ASSERT_EQ(loose.stats.status, RunStatus::kFinished) << loose.stats.message;
    ASSERT_EQ(tight.stats.status, RunStatus::kFinished) << tight.stats.message;
    EXPECT_EQ(loose.stats.energy_work, std::string(kEnergyWorkIntegrated));
    EXPECT_FALSE(loose.stats.energy_work_approximate);
    // The damping dissipates a good part of the energy: the balance is not trivial.
    EXPECT_GT(loose.kinetic.front() + loose.potential.front() -
                  (loose.kinetic.back() + loose.potential.back()),
              1.0);
    // A trapezoid over 0.05 s frames gives about 1e-3 here whatever the tolerance; the
    // integrated work gives the integrator's error, which falls with the tolerance (BDF at
    // rtol 1e-6: 1.1e-5 with the error norm over q and qd alone, 7.4e-6 when it divided by
    // the 13 states, the work included).
    EXPECT_LT(loose.stats.energy_error_max, 3e-5) << MethodName(method);
    EXPECT_LT(tight.stats.energy_error_max, 1e-8) << MethodName(method);
    EXPECT_LT(tight.stats.energy_error_max, loose.stats.energy_error_max / 10)
        << MethodName(method);
  }
}

TEST(WorkQuadratureTest, FixedStepMethodsIntegrateTheWorkToo) {
  const Model model = DampedIrb1600(5.0);
  for (Method method : {Method::kRk4, Method::kDirk}) {
    RunConfig config = DampedSwing(method, 1e-8);
    config.fixed_step = 1e-4;
    const RunResult result = Simulate(model, config);
    ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
    EXPECT_EQ(result.stats.energy_work, std::string(kEnergyWorkIntegrated));
    EXPECT_LT(result.stats.energy_error_max, 1e-6) << MethodName(method);
  }
}

TEST(WorkQuadratureTest, TheWorkIsTheIntegralOfThePower) {
  // Damping only, so the work is -int damping * |qd|^2 dt: compare the quadrature with a fine
  // trapezoid of the power along the (tightly integrated) trajectory.
  const Model model = DampedIrb1600(5.0);
  RunConfig config = DampedSwing(Method::kBdf, 1e-10);
  const DriveSet drives(model, config.drives);
  JointSpaceOde ode(model, drives, /*track_work=*/true);
  ASSERT_EQ(ode.num_quadratures(), 1);
  const Eigen::VectorXd y0 = InitialJointState(config, drives, model.num_dofs());
  std::vector<double> y(y0.data(), y0.data() + y0.size());
  auto integrator =
      MakeIntegrator(ode, 0.0, y.data(), IntegratorOptionsFrom(config, config.duration));
  const int n = model.num_dofs();
  auto power = [&](const std::vector<double>& state) {
    double p = 0.0;
    for (int i = 0; i < n; ++i) p -= 5.0 * state[n + i] * state[n + i];
    return p;
  };
  double trapezoid = 0.0, last = power(y);
  const double h = 1e-3;
  for (int k = 1; k <= 2000; ++k) {
    ASSERT_EQ(integrator->AdvanceTo(h * k, y.data()).status, IntegratorStatus::kOk);
    const double now = power(y);
    trapezoid += 0.5 * h * (now + last);
    last = now;
  }
  double work = 0.0;
  ASSERT_TRUE(integrator->Quadratures(&work));
  EXPECT_LT(work, -1.0);
  EXPECT_NEAR(work, trapezoid, 1e-5 * std::abs(work));
}

// Scenes where nothing does work have no work state; every other joint-space scene
// integrates the work (its motion unchanged bit for bit: work_state_identity_test.cc).
TEST(WorkQuadratureTest, EveryDrivenSceneIntegratesTheWork) {
  const RunResult passive = Simulate(Irb1600(), DampedSwing(Method::kBdf, 1e-6));
  ASSERT_EQ(passive.stats.status, RunStatus::kFinished) << passive.stats.message;
  EXPECT_EQ(passive.stats.energy_work, std::string(kEnergyWorkNone));
  EXPECT_TRUE(passive.work.empty());
  for (const char* scene : {"seed-servo", "seed-run", "stiff-servo"}) {
    RunConfig config = Scene(scene);
    config.formulation = Formulation::kJoint;
    config.duration = 1.0;
    const RunResult driven = Simulate(Irb1600(), config);
    ASSERT_EQ(driven.stats.status, RunStatus::kFinished) << scene << ": " << driven.stats.message;
    EXPECT_EQ(driven.stats.equations, 12) << scene;  // the quadrature is not an equation
    EXPECT_EQ(driven.stats.energy_work, std::string(kEnergyWorkIntegrated)) << scene;
    EXPECT_FALSE(driven.stats.energy_work_approximate) << scene;
    EXPECT_EQ(driven.work.size(), driven.t.size()) << scene;
    EXPECT_NE(driven.work.back(), 0.0) << scene;
  }
}

// The case: seed-servo over 1 s at rtol = atol = 1e-12 reported an energy balance
// error of 0.131 (trust low, "tighten rtol/atol") with frames 0.5 s apart and 0.0017 with
// frames 0.05 s apart: the trapezoid rule over the frames, not the integration. With the work
// integrated with the motion the balance is the integrator's, whatever the output interval.
TEST(WorkQuadratureTest, SeedServoEnergyErrorDoesNotDependOnTheOutputInterval) {
  std::vector<RunResult> results;
  for (double interval : {0.5, 0.05}) {
    RunConfig config = Scene("seed-servo");
    config.duration = 1.0;
    config.output_interval = interval;
    config.rtol = config.atol = 1e-12;
    results.push_back(Simulate(Irb1600(), config));
    const RunStats& s = results.back().stats;
    ASSERT_EQ(s.status, RunStatus::kFinished) << s.message;
    EXPECT_EQ(s.energy_work, std::string(kEnergyWorkIntegrated));
    EXPECT_EQ(s.trust, Trust::kOk) << interval << ": " << s.trust_reason;
    // Integrator level: far below the 0.0017 the 0.05 s trapezoid gave.
    EXPECT_LT(s.energy_error_max, 1e-9) << interval;
  }
  const RunResult& coarse = results[0];
  const RunResult& fine = results[1];
  ASSERT_EQ(coarse.num_frames(), 3);
  ASSERT_EQ(fine.num_frames(), 21);
  // Nearly the same integration (the outputs are interpolated; the step sequences differ by
  // a step or so near the output times): the work and the balance at t = 1 s agree to far
  // below the integrator's error, and the two maxima are both at round-off level, 1e-11.
  const auto balance = [](const RunResult& r, int k) {
    return r.kinetic[k] + r.potential[k] - r.kinetic[0] - r.potential[0] - r.work[k];
  };
  EXPECT_NEAR(coarse.work.back(), fine.work.back(), 1e-9 * std::abs(fine.work.back()));
  EXPECT_NEAR(balance(coarse, 2), balance(fine, 20), 1e-8);
  EXPECT_NEAR(coarse.stats.energy_error_max, fine.stats.energy_error_max, 1e-10);
}

// body-baumgarte integrates the work as well (an ODE); the DAE formulations (IDA) keep the
// trapezoid rule over the frames and say so.
TEST(WorkQuadratureTest, BodyBaumgarteIntegratesTheWorkAndTheDaeFormulationsSaySo) {
  for (double interval : {0.5, 0.05}) {
    RunConfig config = Scene("seed-servo");
    config.formulation = Formulation::kBodyBaumgarte;
    config.duration = 1.0;
    config.output_interval = interval;
    config.rtol = 1e-9;
    config.atol = 1e-11;
    const RunResult result = Simulate(Irb1600(), config);
    const RunStats& s = result.stats;
    ASSERT_EQ(s.status, RunStatus::kFinished) << s.message;
    EXPECT_EQ(s.energy_work, std::string(kEnergyWorkIntegrated));
    EXPECT_EQ(result.work.size(), result.t.size());
    EXPECT_EQ(s.trust, Trust::kOk) << s.trust_reason;
    EXPECT_LT(s.energy_error_max, 1e-5) << interval;
  }
  RunConfig dae = Scene("seed-servo");
  dae.formulation = Formulation::kBodyIndex2;
  dae.method = Method::kIda;
  dae.duration = 0.2;
  const RunResult result = Simulate(Irb1600(), dae);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.energy_work, std::string(kEnergyWorkTrapezoid));
  EXPECT_TRUE(result.stats.energy_work_approximate);
}

}  // namespace
}  // namespace mbstream
