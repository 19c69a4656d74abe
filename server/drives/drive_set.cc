#include "server/drives/drive_set.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "shared/common/check.h"

namespace mbstream {

DriveSet::DriveSet(const Model& model, const std::vector<DriveConfig>& drives) : drives_(drives) {
  MBSTREAM_CHECK_MSG(static_cast<int>(drives_.size()) == model.num_dofs(),
                     "a run must have one drive per joint");
  references_.resize(drives_.size());
  pose_hold_.assign(drives_.size(), 0);
  for (int b = 0; b < model.num_bodies(); ++b) {  // prescribed poses: the rest held
    const Body& body = model.bodies[static_cast<size_t>(b)];
    if (body.nv() == 1) continue;
    const auto first = drives_.begin() + body.v_index;
    if (std::none_of(first, first + body.nv(), [](const DriveConfig& drive) {
          return drive.kind == DriveConfig::Kind::kPrescribed;
        })) {
      continue;
    }
    posed_bodies_.push_back(b);
    for (int k = body.v_index; k < body.v_index + body.nv(); ++k) {
      if (drives_[static_cast<size_t>(k)].kind != DriveConfig::Kind::kPassive) continue;
      drives_[static_cast<size_t>(k)].kind = DriveConfig::Kind::kPrescribed;
      drives_[static_cast<size_t>(k)].trajectory = Trajectory{};
      pose_hold_[static_cast<size_t>(k)] = 1;
    }
  }
  for (size_t i = 0; i < drives_.size(); ++i) {
    const DriveConfig& drive = drives_[i];
    // Joint i's damping (a velocity coordinate: a free or ball joint's coordinates have none).
    const Body& body = model.bodies[static_cast<size_t>(model.BodyOfVelocity(static_cast<int>(i)))];
    const double damping = body.nv() != 1 ? 0.0 : body.joint.damping;
    damping_.push_back(damping);
    if (drive.kind == DriveConfig::Kind::kPrescribed || drive.kind == DriveConfig::Kind::kPdServo) {
      references_[i] = TrajectoryEvaluator(drive.trajectory);
    }
    if (drive.kind == DriveConfig::Kind::kPrescribed) ++num_prescribed_;
    Held held = Held::kNone;
    if (drive.kind == DriveConfig::Kind::kExternal) {
      held = drive.command == DriveConfig::Command::kEffort     ? Held::kEffort
             : drive.command == DriveConfig::Command::kPosition ? Held::kPosition
                                                                : Held::kVelocity;
      external_.push_back(static_cast<int>(i));
    } else if (drive.kind == DriveConfig::Kind::kPdServo && drive.period > 0.0) {
      held = Held::kEffort;
      servos_held_.push_back(static_cast<int>(i));
    }
    held_.push_back(held);
    if (held != Held::kNone) {
      sampled_.push_back(static_cast<int>(i));
      if (period_ == 0.0) period_ = drive.period;
    }
    if (drive.kind != DriveConfig::Kind::kPassive || damping > 0.0) any_work_ = true;
  }
  // The sine terms of ActuatorEfforts, sharing equal arguments. Equal means the same bits,
  // so that sharing never changes a value (0.0 and -0.0 stay apart).
  const auto argument_index = [this](double omega, double phase) {
    const auto same = [](double a, double b) {
      return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
    };
    for (size_t k = 0; k < arguments_.size(); ++k) {
      if (same(arguments_[k].omega, omega) && same(arguments_[k].phase, phase)) {
        return static_cast<int>(k);
      }
    }
    arguments_.push_back({omega, phase});
    return static_cast<int>(arguments_.size()) - 1;
  };
  for (const DriveConfig& drive : drives_) {
    EffortLaw law{drive.kind};
    law.first_term = static_cast<int>(terms_.size());
    if (drive.kind == DriveConfig::Kind::kTorque) {
      law.base = drive.constant;
      terms_.push_back({argument_index(drive.omega, drive.phase), drive.amplitude, 0.0});
    } else if (drive.kind == DriveConfig::Kind::kPdServo) {
      const Trajectory& ref = drive.trajectory;
      law.spline_reference = ref.kind != Trajectory::Kind::kSine;
      law.base = ref.offset;
      law.kp = drive.kp;
      law.kd = drive.kd;
      for (size_t k = 0; !law.spline_reference && k < ref.amplitude.size(); ++k) {
        terms_.push_back({argument_index(ref.omega[k], ref.phase[k]), ref.amplitude[k],
                          ref.amplitude[k] * ref.omega[k]});
      }
    }
    if (drive.kind == DriveConfig::Kind::kExternal) {  // the held setpoints' PD
      law.kp = drive.kp;
      law.kd = drive.kd;
    }
    law.end_term = static_cast<int>(terms_.size());
    laws_.push_back(law);
  }
}

// The sums of TrajectoryEvaluator::SineAt (servo: q_ref, qd_ref) or the torque law
// (constant + amplitude * sin), term by term in the same order; sin_cos(argument, &s, &c)
// supplies the sine and cosine of each term's argument.
template <typename SinCos>
double DriveSet::LawEffort(int joint, double t, double q, double qd, SinCos&& sin_cos) const {
  const EffortLaw& law = laws_[joint];
  double value = law.base, rate = 0.0;
  for (int k = law.first_term; k < law.end_term; ++k) {
    const SineTerm& term = terms_[k];
    double s, c;
    sin_cos(term.argument, &s, &c);
    value += term.amplitude * s;
    rate += term.amplitude_omega * c;
  }
  switch (law.kind) {
    case DriveConfig::Kind::kTorque:
      return value;
    case DriveConfig::Kind::kPdServo:
      if (law.spline_reference) {
        const TrajectoryPoint ref = references_[joint].At(t);
        value = ref.q;
        rate = ref.qd;
      }
      return law.kp * (value - q) + law.kd * (rate - qd);
    case DriveConfig::Kind::kPassive:
    case DriveConfig::Kind::kPrescribed:
    case DriveConfig::Kind::kExternal:
      return 0.0;
  }
  return 0.0;
}

double DriveSet::HeldEffort(int joint, double q, double qd, double held) const {
  const EffortLaw& law = laws_[joint];
  switch (held_[joint]) {
    case Held::kEffort:
      return held;
    case Held::kPosition:
      return law.kp * (held - q) - law.kd * qd;
    case Held::kVelocity:
      return law.kd * (held - qd);
    case Held::kNone:
      break;
  }
  return 0.0;
}

double DriveSet::ActuatorEffort(int joint, double t, double q, double qd) const {
  if (sampled(joint)) return HeldEffort(joint, q, qd, 0.0);
  return LawEffort(joint, t, q, qd, [this, t](int argument, double* s, double* c) {
    ::sincos(arguments_[argument].omega * t + arguments_[argument].phase, s, c);
  });
}

DriveSet::Workspace DriveSet::MakeWorkspace() const {
  Workspace workspace;
  workspace.owner = this;
  workspace.sin.assign(arguments_.size(), 0.0);
  workspace.cos.assign(arguments_.size(), 0.0);
  workspace.held.assign(drives_.size(), 0.0);
  return workspace;
}

void DriveSet::ActuatorEfforts(double t, const double* q, const double* qd, Workspace& workspace,
                               double* effort) const {
  MBSTREAM_CHECK_MSG(
      workspace.owner == this,
      "a DriveSet::Workspace of another DriveSet: make it with this DriveSet's MakeWorkspace()");
  double* const sin = workspace.sin.data();
  double* const cos = workspace.cos.data();
  for (size_t k = 0; k < arguments_.size(); ++k) {
    ::sincos(arguments_[k].omega * t + arguments_[k].phase, &sin[k], &cos[k]);
  }
  const auto shared = [sin, cos](int argument, double* s, double* c) {
    *s = sin[argument];
    *c = cos[argument];
  };
  for (int i = 0; i < size(); ++i) effort[i] = LawEffort(i, t, q[i], qd[i], shared);
  for (const int i : sampled_) effort[i] = HeldEffort(i, q[i], qd[i], workspace.held[i]);
}

void DriveSet::SampleServos(double t, const double* q, const double* qd,
                            Workspace& workspace) const {
  MBSTREAM_CHECK_MSG(
      workspace.owner == this,
      "a DriveSet::Workspace of another DriveSet: make it with this DriveSet's MakeWorkspace()");
  const auto sin_cos = [this, t](int argument, double* s, double* c) {
    ::sincos(arguments_[argument].omega * t + arguments_[argument].phase, s, c);
  };
  for (const int i : servos_held_) workspace.held[i] = LawEffort(i, t, q[i], qd[i], sin_cos);
}

std::vector<int> PrescribedJoints(const DriveSet& drives) {
  std::vector<int> joints;
  for (int i = 0; i < drives.size(); ++i) {
    if (drives.prescribed(i)) joints.push_back(i);
  }
  return joints;
}

}  // namespace mbstream
