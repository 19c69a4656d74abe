// CpuDeadline (thread_cpu_clock.h) answers as reading the thread's CPU clock at every check
// would: never for an infinite deadline, at once for a passed one, and for a deadline ahead
// it says "passed" at the first check at which the CPU clock had reached it.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "server/integrate/thread_cpu_clock.h"

namespace mbstream {
namespace {

TEST(CpuDeadlineTest, InfiniteNeverPasses) {
  CpuDeadline deadline;
  EXPECT_FALSE(deadline.Passed());
  CpuDeadline also(std::numeric_limits<double>::infinity());
  EXPECT_FALSE(also.Passed());
}

TEST(CpuDeadlineTest, APassedDeadlineIsReportedAtOnce) {
  CpuDeadline deadline(ThreadCpuSeconds() - 1e-3);
  EXPECT_TRUE(deadline.Passed());
  EXPECT_TRUE(deadline.Passed());
}

TEST(CpuDeadlineTest, PassesAtTheFirstCheckAfterTheCpuClockReachedIt) {
  const double deadline_s = ThreadCpuSeconds() + 0.02;
  CpuDeadline deadline(deadline_s);
  volatile double sink = 0.0;
  bool passed = false;
  for (long check = 0; check < 100'000'000 && !passed; ++check) {
    for (int k = 0; k < 1000; ++k) sink = sink + std::sqrt(static_cast<double>(k));  // CPU work
    const double before = ThreadCpuSeconds();
    passed = deadline.Passed();
    const double after = ThreadCpuSeconds();
    // (1 µs of slack: the two clocks come from different sources.)
    if (before >= deadline_s + 1e-6) {
      EXPECT_TRUE(passed) << "the CPU clock had passed the deadline before the check";
    }
    if (passed) {
      EXPECT_GE(after, deadline_s) << "reported passed before the CPU clock reached it";
    }
  }
  EXPECT_TRUE(passed);
}

}  // namespace
}  // namespace mbstream
