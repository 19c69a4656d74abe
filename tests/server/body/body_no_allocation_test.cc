// The body formulations' hot path allocates nothing after setup: the DAE residual, its
// coloured Jacobian, the Baumgarte right-hand side, the output readout, and IDA's steps.
#include <gtest/gtest.h>

#include "server/body/body_baumgarte_ode.h"
#include "server/body/body_dae.h"
#include "server/body/body_readout.h"
#include "server/body/consistent_init.h"
#include "server/integrate/ida_colored_jacobian.h"
#include "server/integrate/ida_integrator.h"
#include "server/integrate/integrator.h"
#include "server/sim/integrator_options_from.h"
#include "tests/common/allocation_counter.h"
#include "tests/server/body/body_test_util.h"

namespace mbstream {
namespace {

struct SceneSetup {
  const Model& model = testing::Irb1600();
  RunConfig config;
  DriveSet drives;
  Eigen::VectorXd q0, qd0;
  BodyModel bm;

  explicit SceneSetup(const char* scene)
      : config(testing::Scene(scene)), drives(model, config.drives), q0(6), qd0(6) {
    for (int i = 0; i < 6; ++i) {
      q0(i) = drives.prescribed(i) ? drives.Reference(i, 0.0).q : 0.1 * i;
      qd0(i) = drives.prescribed(i) ? drives.Reference(i, 0.0).qd : 0.3;
    }
    bm = MakeBodyModel(model, drives, q0);
  }
};

TEST(BodyNoAllocationTest, ResidualJacobianRhsAndReadout) {
  for (const char* scene : {"seed-run", "seed-servo"}) {
    SceneSetup s(scene);
    BodyDae dae(s.bm, s.drives, ConstraintLevel::kVelocity);
    BodyInitialState init;
    ASSERT_TRUE(ConsistentInitialState(s.model, s.bm, dae.mechanics(), 0.0, s.q0, s.qd0, &init));
    ColoredJacobian jacobian(dae);
    std::vector<double> r(dae.size()), values(dae.JacobianNonZeros()), ewt(dae.size(), 1e6);
    BodyBaumgarteOde ode(s.bm, s.drives, s.config.baumgarte);
    std::vector<double> ydot(ode.size());
    BodyReadout readout(s.bm, s.drives);
    const long before = testing::AllocationCount();
    int codes = dae.Residual(0.1, init.y.data(), init.yp.data(), r.data());
    codes += jacobian.Evaluate(0.1, 100.0, 0.01, init.y.data(), init.yp.data(), r.data(),
                               ewt.data(), values.data());
    codes += ode.Rhs(0.1, init.y.data(), ydot.data());
    const bool finite = readout.Read(0.1, init.y.data(), /*efforts=*/true);
    EXPECT_EQ(testing::AllocationCount() - before, 0) << scene;
    EXPECT_EQ(codes, 0);
    EXPECT_TRUE(finite);
  }
}

TEST(BodyNoAllocationTest, IdaStepsAfterTheFirstAdvance) {
  for (const auto solver : {IdaOptions::LinearSolver::kKlu, IdaOptions::LinearSolver::kDense}) {
    SceneSetup s("seed-run");
    BodyDae dae(s.bm, s.drives, ConstraintLevel::kVelocity);
    BodyInitialState init;
    ASSERT_TRUE(ConsistentInitialState(s.model, s.bm, dae.mechanics(), 0.0, s.q0, s.qd0, &init));
    IdaOptions options;
    options.base = IntegratorOptionsFrom(s.config, 2.0);
    options.base.rtol = 1e-6;
    options.base.atol = 1e-8;
    options.initial_step = 1e-5;
    options.linear_solver = solver;
    auto integrator = MakeIdaIntegrator(dae, 0.0, init.y.data(), init.yp.data(), options);
    Eigen::VectorXd y = init.y;
    ASSERT_EQ(integrator->AdvanceTo(0.05, y.data()).status, IntegratorStatus::kOk);
    const long before = testing::AllocationCount();
    for (int k = 2; k <= 40; ++k) {
      ASSERT_EQ(integrator->AdvanceTo(0.05 * k, y.data()).status, IntegratorStatus::kOk);
    }
    EXPECT_EQ(testing::AllocationCount() - before, 0) << integrator->name();
    EXPECT_GT(integrator->stats().jac_evals, 1);
  }
}

TEST(BodyNoAllocationTest, BaumgarteStepsAfterTheFirstAdvance) {
  SceneSetup s("seed-servo");
  BodyBaumgarteOde ode(s.bm, s.drives, s.config.baumgarte);
  BodyInitialState init;
  ASSERT_TRUE(ConsistentInitialState(s.model, s.bm, ode.mechanics(), 0.0, s.q0, s.qd0, &init));
  Eigen::VectorXd y = init.y.head(ode.size());
  auto integrator = MakeIntegrator(ode, 0.0, y.data(), IntegratorOptionsFrom(s.config, 2.0));
  ASSERT_EQ(integrator->AdvanceTo(0.05, y.data()).status, IntegratorStatus::kOk);
  const long before = testing::AllocationCount();
  for (int k = 2; k <= 40; ++k) {
    ASSERT_EQ(integrator->AdvanceTo(0.05 * k, y.data()).status, IntegratorStatus::kOk);
  }
  EXPECT_EQ(testing::AllocationCount() - before, 0) << integrator->name();
}

}  // namespace
}  // namespace mbstream
