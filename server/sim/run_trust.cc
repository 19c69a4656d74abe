#include "server/sim/run_trust.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "shared/common/format.h"

namespace mbstream {

namespace {

// Below these no tolerance is meaningful (round-off of the states and their sums).
constexpr double kRoundOffRelative = 1e-10;

// Appends "what value exceeds limit" to `reason` when value > limit.
bool Exceeds(double value, double limit, const char* what, std::string* reason) {
  if (!(value > limit)) return false;
  if (!reason->empty()) *reason += "; ";
  *reason += FormatString("%s %.3g exceeds %.3g", what, value, limit);
  return true;
}

// The limit a run's tolerance allows, between round-off and the fixed cap.
double Limit(double factor, double tolerance, double cap, double floor) {
  return std::clamp(factor * tolerance, floor, cap);
}

// What to change when the constraints drift beyond the tolerance: a formulation that only
// damps the drift (Baumgarte, unprojected methods) or never sees the positions (index 2)
// keeps drifting however tight the tolerance.
std::string DriftRemedy(const RunStats& s) {
  const bool loops = !s.loops.cut_joints.empty();
  // Tighter tolerances shrink such drift and its limit alike.
  if (s.formulation == "body-index2") {
    return "body-index2 holds the velocity constraints only, so its joint points drift apart "
           "with time: use the body-index3 formulation, or body-baumgarte with larger gains";
  }
  if (s.formulation == "body-baumgarte") {
    return "the Baumgarte gains only damp the drift: raise baumgarte alpha/beta, or use the "
           "body-index3 formulation (method ida), which holds the positions";
  }
  if (loops && s.method != "bdf" && s.method != "ida") {
    return FormatString(
        "method %s is not projected onto the loop constraints, whose drift only the Baumgarte "
        "gains damp: use method bdf (projected after each step) or ida (the GGL DAE holds them "
        "to the tolerance), or raise baumgarte alpha/beta",
        s.method.c_str());
  }
  return "";
}

}  // namespace

double TrustLengthOf(const Model& model) {
  std::vector<double> depth(model.bodies.size(), 0.0);  // base to each body's frame
  double reach = 0.0;
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    const Body& body = model.bodies[i];
    const double from = body.parent == kBase ? 0.0 : depth[static_cast<size_t>(body.parent)];
    double travel = 0.0;
    const JointLimits& limits = body.joint.limits;
    if (body.joint.type == JointType::kPrismatic && std::isfinite(limits.upper - limits.lower)) {
      travel = limits.upper - limits.lower;
    }
    depth[i] = from + body.joint.X_PJ.p.norm() + travel;
    reach = std::max(reach, depth[i]);
  }
  for (const Frame& frame : model.frames) {
    const double from = frame.body == kBase ? 0.0 : depth[static_cast<size_t>(frame.body)];
    reach = std::max(reach, from + frame.X_BF.p.norm());
  }
  return std::max(reach, 1e-3);
}

TrustScale TrustScaleOf(const Model& model, const RunConfig& config, Formulation formulation) {
  TrustScale scale;
  scale.rtol = config.rtol;
  scale.atol = config.atol;
  scale.length_m = TrustLengthOf(model);
  const bool fixed_step = config.method == Method::kRk4 || config.method == Method::kEuler;
  scale.tolerance_controlled = !fixed_step && formulation != Formulation::kKinematic;
  return scale;
}

TrustLimits TrustLimitsOf(const TrustScale& s) {
  const double L = std::max(s.length_m, 1e-3);
  TrustLimits limits;
  limits.length = kTrustDriftPosition * std::max(1.0, L);
  if (!s.tolerance_controlled) return limits;
  limits.energy =
      Limit(kTrustEnergyFactor, s.rtol + s.atol / L, kTrustEnergyError, kRoundOffRelative);
  limits.length =
      Limit(kTrustLengthFactor, s.rtol * L + s.atol, limits.length, kRoundOffRelative * L);
  limits.angle =
      Limit(kTrustAngleFactor, s.rtol + s.atol, kTrustDriftOrientation, kRoundOffRelative);
  limits.quaternion =
      Limit(kTrustQuaternionFactor, s.rtol + s.atol, kTrustQuaternionNorm, kRoundOffRelative);
  return limits;
}

void AssessTrust(RunStats* s, const TrustScale& scale) {
  s->trust_reason.clear();
  if (s->status != RunStatus::kFinished) {
    s->trust = Trust::kNotAssessed;
    return;
  }
  const TrustLimits limits = TrustLimitsOf(scale);
  // Two remedies: a failed indicator of the integration asks for tighter tolerances or a
  // smaller step (or, for drift the tolerance cannot reach, another formulation); an energy
  // balance whose work is a trapezoid rule over the output frames carries that rule's error,
  // which only a smaller output interval reduces.
  std::string reason;
  bool integration = false;
  const bool frame_work = s->energy_work_approximate;
  // The approximate balance: the tolerance's share plus the trapezoid rule's own estimated
  // error; without an estimate, the fixed cap.
  const double quadrature = s->energy_quadrature_error_max >= 0.0
                                ? kTrustQuadratureSafety * s->energy_quadrature_error_max
                                : kTrustEnergyErrorApproximate;
  const double energy_limit =
      frame_work ? std::min(kTrustEnergyErrorApproximate, limits.energy + quadrature)
                 : limits.energy;
  const bool energy = Exceeds(s->energy_error_max, energy_limit, "energy balance error", &reason);
  // The trapezoid rule explains the error when its estimate is a fair part of it.
  const bool quadrature_explains = frame_work && quadrature >= 0.1 * s->energy_error_max;
  integration |= energy && !quadrature_explains;
  integration |=
      Exceeds(s->tcp_error_max, limits.length, "TCP error (m) against the closed form", &reason);
  const bool drift =
      Exceeds(s->drift_position_max, limits.length, "constraint drift (m)", &reason) |
      Exceeds(s->drift_orientation_max, limits.angle, "constraint drift (rad)", &reason);
  // Drift that the formulation, not the tolerance, lets grow is remedied by another
  // formulation or method (DriftRemedy), not by tighter tolerances.
  const std::string drift_remedy = drift ? DriftRemedy(*s) : "";
  integration |= drift && drift_remedy.empty();
  integration |=
      Exceeds(s->quaternion_norm_error_max, limits.quaternion, "quaternion norm error", &reason);
  // A penetration deep against the geometry's size is a contact too soft for its load (the
  // compliant law's answer, not the integrator's error): its remedy is the stiffness.
  const bool deep =
      s->contact.active && Exceeds(s->contact.penetration_relative_max, kTrustContactPenetration,
                                   "contact penetration relative to the smaller "
                                   "geometry's size",
                                   &reason);
  if (s->solver.steps > 0) {
    const double rejected =
        static_cast<double>(s->solver.error_test_failures) / static_cast<double>(s->solver.steps);
    integration |=
        Exceeds(rejected, kTrustRejectedPerStep, "rejected steps per accepted step", &reason);
  }
  s->trust = reason.empty() ? Trust::kOk : Trust::kLow;
  if (reason.empty()) return;
  if (scale.tolerance_controlled) {
    reason += FormatString(
        " (limits for the run's relative tolerance %.3g, absolute %.3g, and the model's reach "
        "%.3g m)",
        scale.rtol, scale.atol, scale.length_m);
  }
  std::string remedy;
  if (energy && frame_work && quadrature_explains) {
    // A tree run may switch to the joint formulation, which integrates the work; a run with
    // closed loops (loop_run.h) has no such formulation.
    const bool tree = s->loops.cut_joints.empty();
    remedy = FormatString(
        "the work of drives and damping is the trapezoid rule over the output frames (formulation "
        "%s), whose error the energy balance includes: use a smaller output_interval_s%s",
        s->formulation.c_str(),
        tree ? ", or the joint formulation, which integrates the work with the motion" : "");
  }
  if (!drift_remedy.empty()) {
    if (!remedy.empty()) remedy += "; and ";
    remedy += drift_remedy;
  }
  if (deep) {
    if (!remedy.empty()) remedy += "; and ";
    remedy +=
        "the compliant contact is too soft for its load (the warnings name the pair and the "
        "time): raise the stiffness (contact.stiffness_n_per_m, drake:point_contact_stiffness)";
  }
  if (integration) {
    if (!remedy.empty()) remedy += "; and ";
    remedy += "tighten rtol/atol or use a smaller step (--step) or an adaptive method";
  }
  s->trust_reason = reason + ": the result cannot be trusted; " + remedy;
}

}  // namespace mbstream
