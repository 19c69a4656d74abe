// The energy balance of a run with damping: the work W(t) of drives and damping is a
// quadrature of the ODE, so the energy error measures the integrator, not a trapezoid rule
// over the output frames; undamped scenes keep their ODE.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "server/integrate/integrator.h"
#include "server/sim/initial_state.h"
#include "server/sim/integrator_options_from.h"
#include "server/sim/joint_space_ode.h"
#include "server/sim/simulate.h"
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
    // integrated work gives the integrator's error, which falls with the tolerance.
    EXPECT_LT(loose.stats.energy_error_max, 1e-5) << MethodName(method);
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

// Undamped scenes keep the ODE they had (2n states, the same steps bit for bit: the
// bit-identity tests of the server and the CLI compare such runs): no work state.
TEST(WorkQuadratureTest, UndampedScenesHaveNoWorkState) {
  const RunResult passive = Simulate(Irb1600(), DampedSwing(Method::kBdf, 1e-6));
  ASSERT_EQ(passive.stats.status, RunStatus::kFinished) << passive.stats.message;
  EXPECT_EQ(passive.stats.energy_work, std::string(kEnergyWorkNone));
  RunConfig servo = Scene("seed-servo");
  servo.duration = 1.0;
  const RunResult driven = Simulate(Irb1600(), servo);
  ASSERT_EQ(driven.stats.status, RunStatus::kFinished) << driven.stats.message;
  EXPECT_EQ(driven.stats.equations, 12);
  EXPECT_EQ(driven.stats.energy_work, std::string(kEnergyWorkTrapezoid));
  EXPECT_TRUE(driven.stats.energy_work_approximate);
}

}  // namespace
}  // namespace mbstream
