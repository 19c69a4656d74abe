// Evaluates a joint's reference motion q(t) with its first two derivatives.
#pragma once

#include <vector>

#include "server/drives/drive_config.h"

namespace mbstream {

// q(t), qd(t), qdd(t) of one joint (rad, rad/s, rad/s^2 or m, m/s, m/s^2).
struct TrajectoryPoint {
  double q = 0.0;
  double qd = 0.0;
  double qdd = 0.0;
};

class TrajectoryEvaluator {
 public:
  TrajectoryEvaluator() = default;
  // Precomputes what evaluation needs (spline second derivatives). The trajectory must be
  // valid (server/spec validates user input): MBSTREAM_CHECK otherwise.
  explicit TrajectoryEvaluator(const Trajectory& trajectory);

  // Allocates nothing.
  TrajectoryPoint At(double t) const;

 private:
  TrajectoryPoint SineAt(double t) const;
  TrajectoryPoint SplineAt(double t) const;

  Trajectory trajectory_;
  std::vector<double> second_derivatives_;  // spline: q'' at each knot (natural ends)
};

}  // namespace mbstream
