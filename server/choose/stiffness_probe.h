// What the method choice learns about a scene's stiffness before the run: the largest
// eigenvalue magnitude of the joint-space ODE's Jacobian at a few states, and the cost of one
// right-hand side, from which the step and the cost an explicit method would need follow.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "server/drives/drive_set.h"
#include "server/model/model.h"

namespace mbstream {

struct StiffnessProbe {
  std::vector<double> times;        // s, the sampled states' times
  std::vector<double> eigenvalues;  // 1/s, max |lambda| of df/dy at each (-1 = not estimated)
  double largest = 0.0;             // 1/s, over the samples
  // 1/s, the largest real part of df/dy's eigenvalues over the samples, when positive: the
  // local rate at which nearby solutions (and so errors) separate; 0 when none is positive.
  double separation_rate = 0.0;
  double rhs_cost_s = 0.0;  // s of CPU per right-hand side evaluation
};

// Probes the joint-space ODE of `model` under `drives` at the states y = [q; qd] given with
// their times. Allocates (it runs before the run, never in a step).
StiffnessProbe ProbeStiffness(const Model& model, const DriveSet& drives,
                              const std::vector<double>& times,
                              const std::vector<Eigen::VectorXd>& states);

// The largest stable step of an explicit method whose stability region reaches `reach` along
// the negative real axis (Dormand-Prince about 3.3), for eigenvalue magnitude `largest`.
inline double ExplicitStepLimit(double reach, double largest) {
  return largest > 0.0 ? reach / largest : 1e300;
}

}  // namespace mbstream
