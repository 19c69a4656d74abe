// The CPU time of the calling thread: what a run's CPU budget and its reported cpu_s count.
#pragma once

#include <ctime>

namespace mbstream {

// s of CPU the calling thread has used (CLOCK_THREAD_CPUTIME_ID). Allocates nothing.
inline double ThreadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace mbstream
