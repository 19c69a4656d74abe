// A run's cost budget: how many internal integrator steps and how many seconds of its
// thread's CPU time it may use before it stops with TOO_MUCH_WORK. The defaults scale with
// the simulated duration (steps, CPU) and the model's size (CPU); docs/budgets.md says how
// they were chosen against the shipped scenes.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "server/sim/run_config.h"

namespace mbstream {

// Default step budget: kStepBudgetFloor + kStepsPerSimulatedSecond * duration.
inline constexpr long kStepBudgetFloor = 50'000;
inline constexpr double kStepsPerSimulatedSecond = 100'000.0;
// Default CPU budget: kCpuBudgetFloorS + kCpuPerSimulatedSecondS * duration * size, where
// size = max(1, (num_dofs / 6)^2) (a 6-joint arm is 1).
inline constexpr double kCpuBudgetFloorS = 60.0;
inline constexpr double kCpuPerSimulatedSecondS = 20.0;

long DefaultMaxSteps(double duration_s);
double DefaultMaxCpuSeconds(double duration_s, int num_dofs);

// Fills config's budget fields that are 0 ("default") with the defaults for its duration
// and a model of `num_dofs` joints. Idempotent.
void ResolveBudget(int num_dofs, RunConfig* config);

// Between Simulate and a formulation's run loop: the CPU deadline in; where the integrator
// stopped and the stiffness there out, when the budget ran out.
struct BudgetTracking {
  double cpu_deadline_s = std::numeric_limits<double>::infinity();  // ThreadCpuSeconds()
  double t_stop = 0.0;       // s, the integrator's last good time (kTooMuchWork)
  double eigenvalue = -1.0;  // 1/s, LargestEigenvalueEstimate there; < 0 = none
  std::string advice;        // the formulation's own advice ("; ..."), appended to the message
};

// Why a run's budget ran out, as the last part of its message: what was exhausted, the rate
// (steps per simulated second) and the likely cause.
struct BudgetReport {
  bool cpu = false;        // the CPU budget ran out (else the step budget)
  long steps = 0;          // internal steps taken
  double cpu_s = 0.0;      // s of CPU used
  double t_reached = 0.0;  // s, simulated time reached by the integrator
  double duration = 0.0;   // s, the run's end time
  double last_step = 0.0;  // s, the integrator's last internal step
  // Likely causes, most likely first (from the input checks and the stiffness estimate);
  // empty = none found.
  std::vector<std::string> causes;
  std::string advice;  // appended as is (BudgetTracking::advice)
};

// "budget exhausted: ..." for the run's message.
std::string BudgetMessage(const RunConfig& config, const BudgetReport& report);

}  // namespace mbstream
