// The trust flag of a finished run: its own error indicators (energy balance, TCP error
// against the closed form, constraint drift, step statistics) against limits that follow the
// run's own tolerances, scaled by the model's size. A run that fails one still ends FINISHED,
// with trust kLow, the reason and what to change; docs/budgets.md lists the limits and how
// they were chosen.
#pragma once

#include "server/model/model.h"
#include "server/sim/run_config.h"
#include "server/sim/run_result.h"

namespace mbstream {

// The fixed limits (relative, m for a model of 1 m, rad, counts): the most any run may show,
// whatever its tolerances. A run whose tolerances ask for less gets a tighter limit
// (TrustLimits); a run with no tolerance (a fixed step, or the kinematic formulation) is
// held to these.
inline constexpr double kTrustEnergyError = 1e-2;  // relative energy balance, work exact
// With drive or damping work integrated from the output frames (trapezoid rule: the body
// formulations solved by IDA, the closed-loop runs) the balance carries that quadrature's
// own error: a looser cap, and the remedy named is a smaller output interval.
inline constexpr double kTrustEnergyErrorApproximate = 1e-1;
inline constexpr double kTrustTcpError = 1e-3;          // m per m of reach, TCP error
inline constexpr double kTrustDriftPosition = 1e-3;     // m per m of reach, joint points apart
inline constexpr double kTrustDriftOrientation = 1e-2;  // rad
inline constexpr double kTrustQuaternionNorm = 1e-3;    // | |e| - 1 |
// Rejected steps (error test failures) per accepted step.
inline constexpr double kTrustRejectedPerStep = 1.0;
// A contact's largest penetration relative to the size of the smaller geometry of its pair
// (RunStats::contact): past half of it a point contact no longer describes the touch (a deep
// overlap's normal and witness points, a thin body passed through). From a tenth of it the
// run is warned (ContactLog::kDeepContact).
inline constexpr double kTrustContactPenetration = 0.5;

// How far the global error of an adaptive run may exceed the local tolerance it asked for,
// per indicator. Chosen so that the default tolerances (rtol 1e-6, atol 1e-8) on a model of
// 1 m give the fixed limits above: a run at those tolerances is judged as before, a run at
// rtol 1e-10 two thousand times more strictly.
inline constexpr double kTrustLengthFactor = 1e3;      // x (rtol * L + atol), m
inline constexpr double kTrustAngleFactor = 1e4;       // x (rtol + atol), rad
inline constexpr double kTrustQuaternionFactor = 1e3;  // x (rtol + atol)
inline constexpr double kTrustEnergyFactor = 1e4;      // x (rtol + atol / L), relative
// The trapezoid rule's estimated error (RunStats::energy_quadrature_error_max) counts this
// many times in the approximate energy limit: the estimate is asymptotic.
inline constexpr double kTrustQuadratureSafety = 3.0;

// What the limits scale with.
struct TrustScale {
  double rtol = 1e-6;
  double atol = 1e-8;
  double length_m = 1.0;  // the model's characteristic length (TrustLengthOf)
  // False when rtol/atol do not control the run's error (fixed-step methods, the kinematic
  // formulation): the fixed limits apply.
  bool tolerance_controlled = true;
};

// The largest distance along the tree from the base to any frame (every joint origin and
// frame offset on the way; a prismatic joint's finite travel added), at least 1 mm: a
// mechanism's reach, the length that a relative tolerance scales.
double TrustLengthOf(const Model& model);
// The run's scale: its tolerances and method, the formulation chosen for it, and the model.
TrustScale TrustScaleOf(const Model& model, const RunConfig& config, Formulation formulation);

struct TrustLimits {
  double energy = kTrustEnergyError;      // relative, work exact
  double length = kTrustDriftPosition;    // m: TCP error and constraint drift
  double angle = kTrustDriftOrientation;  // rad
  double quaternion = kTrustQuaternionNorm;
};
TrustLimits TrustLimitsOf(const TrustScale& scale);

// Sets stats->trust and trust_reason: kNotAssessed unless stats->status is kFinished.
void AssessTrust(RunStats* stats, const TrustScale& scale = TrustScale{});

}  // namespace mbstream
