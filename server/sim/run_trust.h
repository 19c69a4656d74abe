// The trust flag of a finished run: its own error indicators (energy balance, TCP error
// against the closed form, constraint drift, step statistics) against fixed limits. A run
// that fails one still ends FINISHED, with trust kLow and the reason; docs/budgets.md lists
// the limits and how they were chosen.
#pragma once

#include "server/sim/run_result.h"

namespace mbstream {

// Limits (relative, m, rad, counts): beyond them the result cannot be trusted.
inline constexpr double kTrustEnergyError = 1e-2;  // relative energy balance, work exact
// With drive or damping work integrated from the output frames (trapezoid rule: the body
// formulations solved by IDA) the balance carries that quadrature's own error: a looser
// limit, and the remedy named is a smaller output interval, not tighter tolerances.
inline constexpr double kTrustEnergyErrorApproximate = 1e-1;
inline constexpr double kTrustTcpError = 1e-3;          // m, TCP against the closed form
inline constexpr double kTrustDriftPosition = 1e-3;     // m, joint points apart
inline constexpr double kTrustDriftOrientation = 1e-2;  // rad
inline constexpr double kTrustQuaternionNorm = 1e-3;    // | |e| - 1 |
// Rejected steps (error test failures) per accepted step.
inline constexpr double kTrustRejectedPerStep = 1.0;

// Sets stats->trust and trust_reason: kNotAssessed unless stats->status is kFinished.
void AssessTrust(RunStats* stats);

}  // namespace mbstream
