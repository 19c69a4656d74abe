// The CPU time of the calling thread: what a run's CPU budget and its reported cpu_s count.
#pragma once

#include <cmath>
#include <ctime>
#include <limits>

namespace mbstream {

// s of CPU the calling thread has used (CLOCK_THREAD_CPUTIME_ID). Allocates nothing.
inline double ThreadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// s on the monotonic clock, read in user space (the vDSO: no system call).
inline double MonotonicSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// A deadline on the calling thread's CPU clock, checked without reading that clock each time:
// it is a system call (1-3 µs in this VM, and the integrators checked it at every output
// frame: 5 % of a server's CPU on seed-servo). A thread's CPU time advances no faster than
// the monotonic clock, so after a reading with `left` s of budget the deadline cannot pass
// before `left` s of monotonic time have: until then Passed() answers from the cheap clock.
// The deadline is noticed at the same checks as when reading the CPU clock every time.
class CpuDeadline {
 public:
  explicit CpuDeadline(double deadline_s = std::numeric_limits<double>::infinity())
      : deadline_s_(deadline_s) {}

  // Whether the thread's CPU clock has reached the deadline (never, for an infinite one).
  bool Passed() {
    if (!std::isfinite(deadline_s_)) return false;
    const double now = MonotonicSeconds();
    if (now < no_read_before_s_) return false;
    const double left = deadline_s_ - ThreadCpuSeconds();
    if (left <= 0.0) return true;
    no_read_before_s_ = now + left;
    return false;
  }

 private:
  double deadline_s_;
  double no_read_before_s_ = -std::numeric_limits<double>::infinity();
};

}  // namespace mbstream
