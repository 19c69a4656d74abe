// The joint-space ODE of a model with ball joints and a free body (quaternions projected after
// every step, ball joints' ABA steps) allocates nothing on the heap once integrating: every
// method, after a first AdvanceTo (tests/common/allocation_counter.h; SUNDIALS's C allocations
// counted too, except in sanitizer builds, where the test skips itself).
#include <gtest/gtest.h>

#include <random>

#include "server/drives/drive_set.h"
#include "server/integrate/integrator.h"
#include "server/model/data.h"
#include "server/sim/joint_space_ode.h"
#include "tests/common/allocation_counter.h"
#include "tests/server/free/free_tree_model.h"

namespace mbstream {
namespace {

TEST(BallNoAllocationTest, IntegratingBallJointsAllocatesNothingAfterTheFirstCall) {
  if (!testing::CountsCAllocations()) {
    GTEST_SKIP() << "malloc is the sanitizer's: C allocations not counted";
  }
  std::mt19937 rng(71);
  const Model model = testing::BallTree(rng);
  const DriveSet drives(model, std::vector<DriveConfig>(static_cast<size_t>(model.nv())));
  Eigen::VectorXd y0(model.nq() + model.nv());
  y0.head(model.nq()) = testing::RandomPositions(model, rng);
  y0.tail(model.nv()) = testing::RandomVelocities(model, rng, 1.0);
  for (const Method method :
       {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk, Method::kRk4, Method::kEuler}) {
    JointSpaceOde ode(model, drives);
    IntegratorOptions options;
    options.method = method;
    options.rtol = 1e-6;
    options.atol = 1e-8;
    options.fixed_step = 1e-3;
    Eigen::VectorXd y = y0;
    auto integrator = MakeIntegrator(ode, 0.0, y0.data(), options);
    ASSERT_EQ(integrator->AdvanceTo(0.01, y.data()).status, IntegratorStatus::kOk);
    const long before = testing::AllocationCount();
    bool ok = true;
    for (int k = 2; k <= 20; ++k) {
      ok = ok && integrator->AdvanceTo(0.01 * k, y.data()).status == IntegratorStatus::kOk;
    }
    const long allocations = testing::AllocationCount() - before;
    EXPECT_TRUE(ok) << MethodName(method);
    EXPECT_EQ(allocations, 0) << MethodName(method);
  }
}

}  // namespace
}  // namespace mbstream
