#include "server/sim/input_sanity.h"

#include <algorithm>
#include <cmath>

#include "server/drives/drive_set.h"
#include "server/dynamics/crba.h"
#include "server/integrate/failure_messages.h"
#include "server/model/data.h"
#include "server/sim/initial_state.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(mid), values.end());
  return values[mid];
}

// Joint i (a velocity coordinate).
std::string JointLabel(const Model& model, int i) {
  return FormatString("joint %d '%s'", i + 1,
                      model.bodies[model.BodyOfVelocity(i)].joint.name.c_str());
}

const char* InertiaUnit(const Model& model, int i) {
  return model.bodies[model.BodyOfVelocity(i)].joint.type == JointType::kRevolute ? "kg*m^2" : "kg";
}

void CheckServo(const Model& model, int i, const DriveConfig& drive, double inertia,
                std::vector<InputWarning>* out) {
  if (!(inertia > 0.0) || !std::isfinite(inertia)) return;
  const double frequency = std::sqrt(std::abs(drive.kp) / inertia);
  if (frequency > kMaxServoFrequency) {
    out->push_back({FormatString("pd_servo.kp = %g on %s gives a closed-loop frequency "
                                 "sqrt(kp / inertia) of %.3g rad/s for the joint's inertia "
                                 "%.3g %s at the initial pose (beyond %g rad/s): a gain that "
                                 "large looks like a typo",
                                 drive.kp, JointLabel(model, i).c_str(), frequency, inertia,
                                 InertiaUnit(model, i), kMaxServoFrequency),
                    frequency});
  }
  const double damping_rate = std::abs(drive.kd) / inertia;
  if (damping_rate > kMaxServoDampingRate) {
    out->push_back({FormatString("pd_servo.kd = %g on %s gives a damping rate kd / inertia of "
                                 "%.3g 1/s for the joint's inertia %.3g %s (beyond %g 1/s): a "
                                 "gain that large looks like a typo",
                                 drive.kd, JointLabel(model, i).c_str(), damping_rate, inertia,
                                 InertiaUnit(model, i), kMaxServoDampingRate),
                    damping_rate});
  }
  // A PD sampled every h (zero-order hold): its velocity term alone maps an error e to
  // e (1 - kd h / inertia) per period, which rings beyond 1 and grows beyond 2.
  const double sampled = damping_rate * drive.period;
  if (drive.period > 0.0 && sampled > 1.0) {
    out->push_back({FormatString("pd_servo.period_s = %g s on %s: kd h / inertia = %.3g for the "
                                 "joint's inertia %.3g %s; a PD sampled every h rings beyond 1 "
                                 "and is unstable beyond 2: give period_s below %.3g s or a "
                                 "smaller kd",
                                 drive.period, JointLabel(model, i).c_str(), sampled, inertia,
                                 InertiaUnit(model, i), inertia / std::abs(drive.kd)),
                    damping_rate});
  }
}

void CheckTrajectory(const Model& model, int i, const char* field, const Trajectory& trajectory,
                     std::vector<InputWarning>* out) {
  if (trajectory.kind != Trajectory::Kind::kSine) return;
  for (size_t k = 0; k < trajectory.omega.size(); ++k) {
    const double omega = trajectory.omega[k];
    const double amplitude = k < trajectory.amplitude.size() ? trajectory.amplitude[k] : 0.0;
    const double phase = k < trajectory.phase.size() ? trajectory.phase[k] : 0.0;
    if (omega == 0.0 && amplitude != 0.0) {
      out->push_back({FormatString("%s.trajectory term %zu on %s has omega = 0 (amplitude %g): "
                                   "the term is the constant amplitude * sin(phase) = %g, not a "
                                   "motion; if a motion was meant, give omega in rad/s",
                                   field, k + 1, JointLabel(model, i).c_str(), amplitude,
                                   amplitude * std::sin(phase)),
                      0.0});
    } else if (std::abs(omega) > kMaxTrajectoryOmega) {
      out->push_back(
          {FormatString("%s.trajectory term %zu on %s has omega = %g rad/s (beyond %g "
                        "rad/s): a frequency that high looks like a typo",
                        field, k + 1, JointLabel(model, i).c_str(), omega, kMaxTrajectoryOmega),
           std::abs(omega)});
    }
  }
}

void CheckDrives(const Model& model, const RunConfig& config, std::vector<InputWarning>* out) {
  const int n = model.num_dofs();
  if (static_cast<int>(config.drives.size()) != n || n == 0) return;
  bool any_servo = false;
  for (const DriveConfig& drive : config.drives) {
    any_servo = any_servo || drive.kind == DriveConfig::Kind::kPdServo;
  }
  Eigen::VectorXd inertia = Eigen::VectorXd::Zero(n);
  if (any_servo) {
    const DriveSet drives(model, config.drives);
    const Eigen::VectorXd y0 = InitialJointState(config, drives, model);
    Data data(model);
    const Eigen::VectorXd q0 = y0.head(model.nq());
    inertia = Crba(model, data, q0).diagonal();
  }
  for (int i = 0; i < n; ++i) {
    const DriveConfig& drive = config.drives[static_cast<size_t>(i)];
    switch (drive.kind) {
      case DriveConfig::Kind::kPdServo:
        CheckServo(model, i, drive, inertia(i), out);
        CheckTrajectory(model, i, "pd_servo", drive.trajectory, out);
        break;
      case DriveConfig::Kind::kPrescribed:
        CheckTrajectory(model, i, "prescribed", drive.trajectory, out);
        break;
      case DriveConfig::Kind::kTorque:
        if (std::abs(drive.omega) > kMaxTrajectoryOmega) {
          out->push_back(
              {FormatString("torque.omega = %g rad/s on %s (beyond %g rad/s) looks "
                            "like a typo",
                            drive.omega, JointLabel(model, i).c_str(), kMaxTrajectoryOmega),
               std::abs(drive.omega)});
        }
        break;
      case DriveConfig::Kind::kPassive:
      case DriveConfig::Kind::kExternal:
        break;
    }
  }
}

void CheckModel(const Model& model, std::vector<InputWarning>* out) {
  std::vector<double> masses, lengths;
  for (const Body& body : model.bodies) {
    if (body.inertia.mass > 0.0) masses.push_back(body.inertia.mass);
    const double length = body.joint.X_PJ.p.norm();
    if (length > 0.0) lengths.push_back(length);
  }
  const double mass_median = Median(masses);
  if (masses.size() >= 2 && mass_median > 0.0) {
    for (const Body& body : model.bodies) {
      const double m = body.inertia.mass;
      if (!(m > 0.0)) continue;
      const double decades = std::abs(std::log10(m / mass_median));
      if (decades > kMassOrdersFromMedian) {
        out->push_back({FormatString("link '%s' has mass %g kg, %.0f orders of magnitude from "
                                     "the model's median body mass %g kg: check its units "
                                     "(g or t for kg?)",
                                     body.name.c_str(), m, decades, mass_median),
                        0.0});
      }
    }
  }
  const double length_median = Median(lengths);
  if (lengths.size() >= 2 && length_median > 0.0) {
    for (const Body& body : model.bodies) {
      const double length = body.joint.X_PJ.p.norm();
      if (!(length > 0.0)) continue;
      const double decades = std::log10(length / length_median);
      if (decades > kLengthOrdersAboveMedian) {
        out->push_back({FormatString("joint '%s' has its origin %g m from its parent's frame, "
                                     "%.0f orders of magnitude beyond the model's median %g m: "
                                     "check its units (mm for m?)",
                                     body.joint.name.c_str(), length, decades, length_median),
                        0.0});
      }
    }
  }
}

}  // namespace

std::vector<InputWarning> CheckInputSanity(const Model& model, const RunConfig& config) {
  std::vector<InputWarning> warnings;
  CheckModel(model, &warnings);
  CheckDrives(model, config, &warnings);
  std::stable_sort(warnings.begin(), warnings.end(),
                   [](const InputWarning& a, const InputWarning& b) { return a.rate > b.rate; });
  return warnings;
}

std::vector<std::string> WarningMessages(const std::vector<InputWarning>& warnings) {
  std::vector<std::string> messages;
  messages.reserve(warnings.size());
  for (const InputWarning& warning : warnings) messages.push_back(warning.message);
  return messages;
}

}  // namespace mbstream
