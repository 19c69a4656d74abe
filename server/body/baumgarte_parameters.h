// The feedback gains of the body-baumgarte formulation's constraint stabilisation.
#pragma once

namespace mbstream {

struct BaumgarteParameters {
  double alpha = 10.0;  // 1/s, velocity-error feedback
  double beta = 25.0;   // 1/s^2, position-error feedback
  bool operator==(const BaumgarteParameters&) const = default;
};

}  // namespace mbstream
