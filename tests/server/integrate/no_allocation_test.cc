// After the first call, a successful AdvanceTo allocates nothing on the heap: not in
// mbstream and not inside SUNDIALS (C code, which operator new would not see). malloc,
// calloc and realloc are interposed for this test executable and count while armed.
#include <atomic>
#include <cstddef>

#include <gtest/gtest.h>

#include "server/integrate/integrator.h"
#include "tests/common/sanitized_build.h"
#include "tests/server/integrate/test_systems.h"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};

void Count() {
  if (g_counting.load(std::memory_order_relaxed)) {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
  }
}
}  // namespace

// Under a sanitizer (MBSTREAM_SANITIZED, tests/common/sanitized_build.h) malloc is the
// sanitizer's: replacing it would mix two allocators (ASan aborts at start-up), so this test
// program then counts nothing and its tests are skipped.

#ifndef MBSTREAM_SANITIZED
// glibc's own allocator entry points, which the replacements forward to.
extern "C" void* __libc_malloc(size_t size);
extern "C" void* __libc_calloc(size_t count, size_t size);
extern "C" void* __libc_realloc(void* pointer, size_t size);

extern "C" void* malloc(size_t size) noexcept {
  Count();
  return __libc_malloc(size);
}
extern "C" void* calloc(size_t count, size_t size) noexcept {
  Count();
  return __libc_calloc(count, size);
}
extern "C" void* realloc(void* pointer, size_t size) noexcept {
  Count();
  return __libc_realloc(pointer, size);
}
#endif

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
  g_allocations = 0;
  g_counting = true;
  bool ok = true;
  for (int k = 2; k <= outputs; ++k) {
    ok = ok && integrator->AdvanceTo(k * interval, y).status == IntegratorStatus::kOk;
  }
  g_counting = false;
  EXPECT_TRUE(ok) << integrator->name();
  return g_allocations.load();
}

// Skips the calling test in a sanitizer build (see MBSTREAM_SANITIZED).
#ifdef MBSTREAM_SANITIZED
#define SKIP_IF_SANITIZED() GTEST_SKIP() << "malloc is the sanitizer's: allocations not counted"
#else
#define SKIP_IF_SANITIZED() (void)0
#endif

TEST(NoAllocationTest, CountingWorks) {
  SKIP_IF_SANITIZED();
  g_allocations = 0;
  g_counting = true;
  void* p = malloc(64);
  int* q = new int(3);
  g_counting = false;
  free(p);
  delete q;
  EXPECT_EQ(g_allocations.load(), 2);
}

TEST(NoAllocationTest, AdvanceToDoesNotAllocateAfterTheFirstCall) {
  SKIP_IF_SANITIZED();
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
  SKIP_IF_SANITIZED();
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
