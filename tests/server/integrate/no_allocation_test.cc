// After the first call, a successful AdvanceTo allocates nothing on the heap: not in
// mbstream and not inside SUNDIALS (C code: tests/common/allocation_counter.h counts its
// malloc calls too, except in sanitizer builds, where these tests skip themselves).
#include <gtest/gtest.h>

#include "server/integrate/integrator.h"
#include "tests/common/allocation_counter.h"
#include "tests/server/integrate/test_systems.h"

namespace mbstream {
namespace {

using testing::HarmonicOscillator;
using testing::Options;
using testing::StiffRelaxation;

// Heap allocations made by AdvanceTo over outputs 2..n, after a first call.
long AllocationsAfterFirstCall(OdeSystem& system, const IntegratorOptions& options,
                               const double* y0, double* y, int outputs, double interval) {
  auto integrator = MakeIntegrator(system, 0.0, y0, options);
  EXPECT_EQ(integrator->AdvanceTo(interval, y).status, IntegratorStatus::kOk);
  const long before = testing::AllocationCount();
  bool ok = true;
  for (int k = 2; k <= outputs; ++k) {
    ok = ok && integrator->AdvanceTo(k * interval, y).status == IntegratorStatus::kOk;
  }
  const long allocations = testing::AllocationCount() - before;
  EXPECT_TRUE(ok) << integrator->name();
  return allocations;
}

// SUNDIALS allocates with C's malloc: skips the calling test where that is not counted.
#define SKIP_UNLESS_C_COUNTED()                                             \
  if (!testing::CountsCAllocations()) {                                     \
    GTEST_SKIP() << "malloc is the sanitizer's: C allocations not counted"; \
  }

TEST(NoAllocationTest, AdvanceToDoesNotAllocateAfterTheFirstCall) {
  SKIP_UNLESS_C_COUNTED();
  for (Method method :
       {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk, Method::kRk4, Method::kEuler}) {
    for (bool jacobian : {false, true}) {
      HarmonicOscillator system(2.0 * M_PI, jacobian);
      const double y0[2] = {1.0, 0.0};
      double y[2];
      IntegratorOptions options = Options(method, 2.0);
      options.fixed_step = 0.003;
      EXPECT_EQ(AllocationsAfterFirstCall(system, options, y0, y, 40, 0.05), 0)
          << MethodName(method) << (jacobian ? " with Jacobian" : "");
    }
  }
  for (const char* table : {"verner", "fehlberg", "bogacki-shampine"}) {
    HarmonicOscillator system(2.0 * M_PI);
    const double y0[2] = {1.0, 0.0};
    double y[2];
    IntegratorOptions options = Options(Method::kErk, 2.0);
    options.erk_table = table;
    EXPECT_EQ(AllocationsAfterFirstCall(system, options, y0, y, 40, 0.05), 0) << table;
  }
}

TEST(NoAllocationTest, StiffImplicitRunsDoNotAllocate) {
  SKIP_UNLESS_C_COUNTED();
  for (Method method : {Method::kBdf, Method::kDirk}) {
    StiffRelaxation system(1000.0);
    const double y0[1] = {1.0};
    double y[1];
    EXPECT_EQ(AllocationsAfterFirstCall(system, Options(method, 10.0), y0, y, 100, 0.1), 0)
        << MethodName(method);
  }
}

}  // namespace
}  // namespace mbstream
