#include "server/integrate/ida_system.h"

#include <algorithm>
#include <cmath>

namespace mbstream {

void MultiplierTolerances(int size, int first_multiplier, double atol, const double* y0,
                          double* atols) {
  double scale = 1.0;
  for (int i = first_multiplier; i < size; ++i) scale = std::max(scale, std::abs(y0[i]));
  const double multipliers = std::max(atol, kMultiplierNoiseFloor * scale);
  for (int i = 0; i < size; ++i) atols[i] = i < first_multiplier ? atol : multipliers;
}

}  // namespace mbstream
