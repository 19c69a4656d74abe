// The hot-loop algorithms allocate nothing on the heap (tests/common/allocation_counter.h).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <vector>

#include "server/dynamics/aba.h"
#include "server/dynamics/crba.h"
#include "server/dynamics/energy.h"
#include "server/dynamics/hybrid_dynamics.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/kinematics/point_jacobian.h"
#include "tests/common/allocation_counter.h"
#include "tests/common/test_models.h"

namespace mbstream {
namespace {

// The counter itself: it sees C++'s new and, outside sanitizer builds, C's allocator.
// The pointers go through volatile variables: the compiler may not elide the allocations.
TEST(AllocationCounterTest, CountsNewAndMalloc) {
  int* volatile q = nullptr;
  long before = testing::AllocationCount();
  q = new int(3);
  EXPECT_EQ(testing::AllocationCount() - before, 1);
  delete q;
  if (!testing::CountsCAllocations()) GTEST_SKIP() << "C allocations are not counted here";
  void* volatile p = nullptr;
  void* volatile a = nullptr;
  before = testing::AllocationCount();
  p = std::malloc(64);
  a = std::aligned_alloc(64, 128);
  p = std::realloc(p, 4096);
  EXPECT_EQ(testing::AllocationCount() - before, 3);
  std::free(p);
  std::free(a);
}

TEST(NoAllocationTest, PhysicsAlgorithmsDoNotAllocate) {
  for (const Model& model : {testing::Irb1600Model(), testing::BranchingModel()}) {
    Data data(model);
    std::mt19937 rng(3);
    const int n = model.num_dofs();
    const Eigen::VectorXd q = testing::RandomVector(rng, n, 1.0);
    const Eigen::VectorXd qd = testing::RandomVector(rng, n, 1.0);
    const Eigen::VectorXd tau = testing::RandomVector(rng, n, 1.0);
    std::vector<unsigned char> prescribed(n, 0);
    prescribed[n / 2] = 1;
    double sink = 0.0;
    const long before = testing::AllocationCount();
    ForwardKinematics(model, data, q);
    PointJacobian(model, data, model.tcp_frame, data.J);
    sink += Rnea(model, data, q, qd, tau)(0);
    sink += NonlinearEffects(model, data, q, qd)(0);
    sink += GravityVector(model, data, q)(0);
    sink += Crba(model, data, q)(0, 0);
    sink += Aba(model, data, q, qd, tau)(0);
    sink += HybridAba(model, data, q, qd, tau, tau, prescribed)(0);
    sink += KineticEnergy(model, data, q, qd);
    sink += PotentialEnergy(model, data);
    EXPECT_EQ(testing::AllocationCount() - before, 0) << model.name;
    EXPECT_TRUE(std::isfinite(sink));
  }
}

}  // namespace
}  // namespace mbstream
