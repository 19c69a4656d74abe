// The hot-loop algorithms allocate nothing on the heap: a counting global operator new.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "server/dynamics/aba.h"
#include "server/dynamics/crba.h"
#include "server/dynamics/energy.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/kinematics/point_jacobian.h"
#include "tests/common/allocation_counter.h"
#include "tests/common/test_models.h"

namespace mbstream {
namespace {

TEST(NoAllocationTest, PhysicsAlgorithmsDoNotAllocate) {
  for (const Model& model : {testing::Irb1600Model(), testing::BranchingModel()}) {
    Data data(model);
    std::mt19937 rng(3);
    const int n = model.num_dofs();
    const Eigen::VectorXd q = testing::RandomVector(rng, n, 1.0);
    const Eigen::VectorXd qd = testing::RandomVector(rng, n, 1.0);
    const Eigen::VectorXd tau = testing::RandomVector(rng, n, 1.0);
    double sink = 0.0;
    const long before = testing::AllocationCount();
    ForwardKinematics(model, data, q);
    PointJacobian(model, data, model.tcp_frame, data.J);
    sink += Rnea(model, data, q, qd, tau)(0);
    sink += NonlinearEffects(model, data, q, qd)(0);
    sink += GravityVector(model, data, q)(0);
    sink += Crba(model, data, q)(0, 0);
    sink += Aba(model, data, q, qd, tau)(0);
    sink += KineticEnergy(model, data, q, qd);
    sink += PotentialEnergy(model, data);
    EXPECT_EQ(testing::AllocationCount() - before, 0) << model.name;
    EXPECT_TRUE(std::isfinite(sink));
  }
}

TEST(NoAllocationTest, CounterSeesAllocations) {
  const long before = testing::AllocationCount();
  auto* p = new std::vector<double>(100);
  EXPECT_GE(testing::AllocationCount() - before, 2);
  delete p;
}

}  // namespace
}  // namespace mbstream
