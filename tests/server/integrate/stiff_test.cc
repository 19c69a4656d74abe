// On a stiff problem the implicit methods take far fewer steps than the explicit one.
#include <cmath>

#include <gtest/gtest.h>

#include "server/integrate/integrator.h"
#include "tests/server/integrate/test_systems.h"

namespace mbstream {
namespace {

using testing::Options;
using testing::StiffRelaxation;

struct StiffRun {
  SolverStats stats;
  double max_error = 0.0;
};

StiffRun RunStiff(Method method) {
  StiffRelaxation system(1000.0);
  const double y0[1] = {1.0};
  auto integrator = MakeIntegrator(system, 0.0, y0, Options(method, 10.0, 1e-6));
  StiffRun run;
  double y[1];
  for (int k = 1; k <= 100; ++k) {
    const double t = 0.1 * k;
    const AdvanceResult result = integrator->AdvanceTo(t, y);
    EXPECT_EQ(result.status, IntegratorStatus::kOk) << result.message;
    run.max_error = std::max(run.max_error, std::abs(y[0] - system.Exact(t)));
  }
  run.stats = integrator->stats();
  return run;
}

TEST(StiffTest, ImplicitMethodsTakeFarFewerStepsThanErk) {
  const StiffRun erk = RunStiff(Method::kErk);
  const StiffRun bdf = RunStiff(Method::kBdf);
  const StiffRun dirk = RunStiff(Method::kDirk);
  EXPECT_GE(erk.stats.steps, 20 * bdf.stats.steps)
      << "erk " << erk.stats.steps << " vs bdf " << bdf.stats.steps;
  EXPECT_GE(erk.stats.steps, 10 * dirk.stats.steps)
      << "erk " << erk.stats.steps << " vs dirk " << dirk.stats.steps;
  EXPECT_LT(bdf.max_error, 1e-4);
  EXPECT_LT(dirk.max_error, 1e-4);
  EXPECT_LT(erk.max_error, 1e-4);
  // Newton with a Jacobian: iterations, Jacobians and a plausible order.
  EXPECT_GT(bdf.stats.jac_evals, 0);
  EXPECT_GE(bdf.stats.nonlinear_iterations, bdf.stats.steps);
  EXPECT_GE(bdf.stats.last_order, 1);
  EXPECT_LE(bdf.stats.last_order, 5);
  EXPECT_GT(dirk.stats.jac_evals, 0);
  EXPECT_GE(dirk.stats.nonlinear_iterations, dirk.stats.steps);
  // A stable explicit step is bounded by the stiff eigenvalue: h < ~3.3 / 1000.
  EXPECT_LT(erk.stats.last_step, 5e-3);
  EXPECT_GT(bdf.stats.last_step, 1e-2);
}

}  // namespace
}  // namespace mbstream
