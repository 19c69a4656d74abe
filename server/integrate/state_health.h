// The health test of a state: every component finite and within the divergence limit (the
// states under error control; appended quadratures need only be finite).
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

// True when every y[i] is finite and the first `limited` (the states under error control;
// appended quadratures, such as the work of the drives, may grow past the limit) are within
// it. Allocates nothing.
inline bool IsHealthyState(const double* y, int size, int limited, double limit) {
  for (int i = 0; i < size; ++i) {
    if (!(std::abs(y[i]) <= (i < limited ? limit : HUGE_VAL))) return false;
  }
  return true;
}

// The states under the divergence limit of a system of `size` states with
// IntegratorOptions::error_states = `error_states` (0 = all).
inline int LimitedStates(int size, int error_states) {
  return error_states > 0 && error_states < size ? error_states : size;
}

// True when every y[i] is finite. Allocates nothing.
inline bool IsFiniteState(const double* y, int size) {
  for (int i = 0; i < size; ++i) {
    if (!std::isfinite(y[i])) return false;
  }
  return true;
}

}  // namespace mbstream
