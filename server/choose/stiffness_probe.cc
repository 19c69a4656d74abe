#include "server/choose/stiffness_probe.h"

#include <algorithm>

#include "server/integrate/stiffness_estimate.h"
#include "server/integrate/thread_cpu_clock.h"
#include "server/sim/joint_space_ode.h"

namespace mbstream {

namespace {

constexpr int kTimedEvaluations = 40;  // right-hand sides timed for their cost

}  // namespace

StiffnessProbe ProbeStiffness(const Model& model, const DriveSet& drives,
                              const std::vector<double>& times,
                              const std::vector<Eigen::VectorXd>& states) {
  StiffnessProbe probe;
  JointSpaceOde ode(model, drives);
  for (size_t k = 0; k < states.size(); ++k) {
    const JacobianSpectrum spectrum = EstimateJacobianSpectrum(ode, times[k], states[k].data());
    probe.times.push_back(times[k]);
    probe.eigenvalues.push_back(spectrum.ok ? spectrum.largest_magnitude : -1.0);
    if (!spectrum.ok) continue;
    probe.largest = std::max(probe.largest, spectrum.largest_magnitude);
    probe.separation_rate = std::max(probe.separation_rate, spectrum.largest_real);
  }
  if (!states.empty()) {
    Eigen::VectorXd ydot(ode.size());
    const double cpu0 = ThreadCpuSeconds();
    for (int k = 0; k < kTimedEvaluations; ++k) ode.Rhs(times[0], states[0].data(), ydot.data());
    probe.rhs_cost_s = (ThreadCpuSeconds() - cpu0) / kTimedEvaluations;
  }
  return probe;
}

}  // namespace mbstream
