// Sanity checks of a run's physical inputs, before any integration: values that are legal
// but absurd for the model (a servo gain whose closed-loop frequency is beyond 1e6 rad/s for
// the joint's inertia, a body mass or link length many orders of magnitude from the rest of
// the model, a sine term with omega 0) become warnings that name the field and the value.
// They do not stop the run; a run whose budget runs out cites them as the likely cause.
#pragma once

#include <string>
#include <vector>

#include "server/model/model.h"
#include "server/sim/run_config.h"

namespace mbstream {

// Thresholds (docs/budgets.md).
inline constexpr double kMaxServoFrequency = 1e6;        // rad/s, sqrt(kp / M_ii(q0))
inline constexpr double kMaxServoDampingRate = 1e9;      // 1/s, kd / M_ii(q0)
inline constexpr double kMaxTrajectoryOmega = 1e6;       // rad/s
inline constexpr double kMassOrdersFromMedian = 6.0;     // decades from the median body mass
inline constexpr double kLengthOrdersAboveMedian = 4.0;  // decades above the median offset

struct InputWarning {
  std::string message;  // names the field (and joint or body) and its value
  // 1/s: the time scale the value imposes on the motion (a servo's closed-loop frequency or
  // damping rate); 0 for warnings that imply none.
  double rate = 0.0;
};

// The warnings for `config` (validated by server/spec: one drive per joint) on `model`,
// highest rate first. Allocates (call it once, at the start of a run).
std::vector<InputWarning> CheckInputSanity(const Model& model, const RunConfig& config);

// Just the messages.
std::vector<std::string> WarningMessages(const std::vector<InputWarning>& warnings);

}  // namespace mbstream
