// The health test of a state: every component finite and within the divergence limit.
#pragma once

#include <cmath>

namespace mbstream {

// True when every y[i] is finite and |y[i]| <= limit. Allocates nothing.
inline bool IsHealthyState(const double* y, int size, double limit) {
  for (int i = 0; i < size; ++i) {
    // Written so that NaN fails: every comparison with NaN is false.
    if (!(std::abs(y[i]) <= limit)) return false;
  }
  return true;
}

// True when every y[i] is finite. Allocates nothing.
inline bool IsFiniteState(const double* y, int size) {
  for (int i = 0; i < size; ++i) {
    if (!std::isfinite(y[i])) return false;
  }
  return true;
}

}  // namespace mbstream
