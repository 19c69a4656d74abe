// RunSpec -> RunConfig: every field validated, defaults applied, drives matched to joints.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <optional>

#include "server/spec/contact_spec.h"
#include "server/spec/initial_bodies_spec.h"
#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"
#include "shared/common/did_you_mean.h"

namespace mbstream {
namespace {

std::string Format(double value) {
  std::array<char, 32> buffer;
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

// A name from the request as it may appear in a message: at most 64 bytes, then "...".
std::string Quote(const std::string& name) {
  constexpr size_t kShown = 64;
  return "'" + (name.size() <= kShown ? name : name.substr(0, kShown) + "...") + "'";
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names) joined += (joined.empty() ? "" : ", ") + name;
  return joined.empty() ? "(none)" : joined;
}

std::string FormulationNames() {
  std::vector<std::string> names;
  for (auto f : {Formulation::kAuto, Formulation::kKinematic, Formulation::kJoint,
                 Formulation::kBodyIndex3, Formulation::kBodyIndex2, Formulation::kBodyBaumgarte}) {
    names.push_back(FormulationName(f));
  }
  return JoinNames(names);
}

std::string MethodNames() {
  std::vector<std::string> names;
  for (auto m : {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk, Method::kIda,
                 Method::kRk4, Method::kEuler}) {
    names.push_back(MethodName(m));
  }
  return JoinNames(names);
}

constexpr size_t kMaxNameBytes = 256;      // joint, method, formulation and table names
constexpr int kMaxSineTerms = 64;          // terms of one sum of sines
constexpr int kMaxSplinePoints = 100000;   // points of one spline
constexpr size_t kMaxSpecBytes = 4 << 20;  // the whole spec, encoded
constexpr double kMaxDuration = 1e9;       // s, simulated
constexpr double kMaxFrames = 1e9;         // duration_s / output_interval_s
constexpr double kMinRealtime = 1e-3;      // simulated s per wall-clock s (0 = unpaced)
constexpr double kMaxRealtime = 1e9;
// s: a step below this is no step a mechanism needs, and SUNDIALS refuses steps near the
// smallest double (CV_ILL_INPUT): max_step_s and fixed_step_s are refused below it.
constexpr double kMinStep = 1e-10;
constexpr double kMaxGravity = 1e4;  // m/s^2 per component (1,000 g), beyond any test rig
constexpr int kMaxRetries = 100;     // attempts after the first

// Builds the messages: "<source>: <field>: <problem>; <what to do>".
class Checker {
 public:
  explicit Checker(const std::string& source) : source_(source) {}

  [[noreturn]] void Fail(const std::string& field, const std::string& problem) const {
    throw InputError(source_ + ": " + field + ": " + problem);
  }

  double Finite(double value, const std::string& field, const std::string& unit) const {
    if (!std::isfinite(value)) {
      Fail(field,
           "is " + Format(value) + ", not a finite number; give a finite value (" + unit + ")");
    }
    return value;
  }

  double Positive(double value, const std::string& field, const std::string& unit,
                  const std::string& advice) const {
    Finite(value, field, unit);
    if (!(value > 0.0)) {
      Fail(field, "must be > 0 (" + unit + "), got " + Format(value) + "; " + advice);
    }
    return value;
  }

  double NonNegative(double value, const std::string& field, const std::string& unit,
                     const std::string& advice) const {
    Finite(value, field, unit);
    if (value < 0.0)
      Fail(field, "must be >= 0 (" + unit + "), got " + Format(value) + "; " + advice);
    return value;
  }

  // A name field: at most kMaxNameBytes bytes, no control characters (a NUL would cut
  // every message that quotes it).
  const std::string& Name(const std::string& value, const std::string& field) const {
    if (value.size() > kMaxNameBytes) {
      Fail(field, "is " + std::to_string(value.size()) + " bytes long, more than " +
                      std::to_string(kMaxNameBytes) + "; give a name (" +
                      Quote(value.substr(0, 64)) + "...)");
    }
    if (std::any_of(value.begin(), value.end(),
                    [](char c) { return static_cast<unsigned char>(c) < 0x20; })) {
      Fail(field, "holds a control character (a byte below 0x20, e.g. a NUL); give the name " +
                      std::string("as the model spells it"));
    }
    return value;
  }

  // A repeated field: at most `max` entries.
  void Count(int count, int max, const std::string& field, const std::string& advice) const {
    if (count > max) {
      Fail(field, "has " + std::to_string(count) + " entries, more than " + std::to_string(max) +
                      "; " + advice);
    }
  }

  double Tolerance(double value, const std::string& field, const std::string& advice) const {
    Finite(value, field, "dimensionless");
    if (!(value > 0.0 && value < 1.0)) {
      Fail(field, "must be in (0, 1), got " + Format(value) + "; " + advice);
    }
    return value;
  }

 private:
  const std::string& source_;
};

constexpr char kJointUnit[] = "rad or m";

// One value per coordinate named in `names` (or none), each finite. `kind` names the
// coordinates in the message: "joints" for a tree's, "position coordinates" where free joints
// make positions and velocities differ.
Eigen::VectorXd JointVector(const google::protobuf::RepeatedField<double>& values,
                            const std::vector<std::string>& names, const char* kind,
                            const std::string& field, const std::string& unit,
                            const Checker& check) {
  const int n = static_cast<int>(names.size());
  if (!values.empty() && values.size() != n) {
    const bool joints = std::string(kind) == "joints";
    check.Fail(field,
               "has " + std::to_string(values.size()) + " values but the model has " +
                   std::to_string(n) + " " + kind + " (" + JoinNames(names) + "); give none or " +
                   (joints ? "one per joint (" + unit + ") in the model's joint order"
                           : "one per coordinate (" + unit +
                                 ") in the model's order; a free joint's are x y z qw qx qy qz "
                                 "(positions) and vx vy vz wx wy wz (velocities), a ball "
                                 "joint's qw qx qy qz and wx wy wz, docs/free_bodies.md"));
  }
  Eigen::VectorXd vector(values.size());
  for (int i = 0; i < values.size(); ++i) {
    vector[i] = check.Finite(
        values[i], field + "[" + std::to_string(i) + "] (" + names[static_cast<size_t>(i)] + ")",
        unit);
  }
  return vector;
}

Trajectory ToTrajectory(const v1::Trajectory& spec, const std::string& field,
                        const Checker& check) {
  Trajectory trajectory;
  switch (spec.kind_case()) {
    case v1::Trajectory::kSumOfSines: {
      const v1::SumOfSines& sines = spec.sum_of_sines();
      const std::string where = field + ".sum_of_sines";
      trajectory.kind = Trajectory::Kind::kSine;
      trajectory.offset = check.Finite(sines.offset(), where + ".offset", kJointUnit);
      check.Count(sines.terms_size(), kMaxSineTerms, where + ".terms",
                  "a trajectory of many harmonics is better given as a spline");
      for (int k = 0; k < sines.terms_size(); ++k) {
        const std::string term = where + ".terms[" + std::to_string(k) + "]";
        const v1::Sine& sine = sines.terms(k);
        trajectory.amplitude.push_back(
            check.Finite(sine.amplitude(), term + ".amplitude", kJointUnit));
        trajectory.omega.push_back(check.Finite(sine.omega(), term + ".omega", "rad/s"));
        trajectory.phase.push_back(check.Finite(sine.phase(), term + ".phase", "rad"));
      }
      return trajectory;
    }
    case v1::Trajectory::kSpline: {
      const v1::Spline& spline = spec.spline();
      const std::string where = field + ".spline";
      trajectory.kind = Trajectory::Kind::kSpline;
      if (spline.times_s_size() != spline.values_size()) {
        check.Fail(where, "times_s has " + std::to_string(spline.times_s_size()) +
                              " entries but values has " + std::to_string(spline.values_size()) +
                              "; give one value per time");
      }
      check.Count(spline.times_s_size(), kMaxSplinePoints, where + ".times_s",
                  "resample the trajectory more coarsely");
      if (spline.times_s_size() < 2) {
        check.Fail(where, "needs at least 2 points, has " + std::to_string(spline.times_s_size()) +
                              "; give at least 2 (times_s, values) pairs");
      }
      for (int k = 0; k < spline.times_s_size(); ++k) {
        const std::string index = "[" + std::to_string(k) + "]";
        trajectory.times.push_back(
            check.Finite(spline.times_s(k), where + ".times_s" + index, "s"));
        trajectory.values.push_back(
            check.Finite(spline.values(k), where + ".values" + index, kJointUnit));
        if (k > 0 && !(trajectory.times[k] > trajectory.times[k - 1])) {
          check.Fail(where + ".times_s" + index,
                     Format(trajectory.times[k]) + " s is not after times_s[" +
                         std::to_string(k - 1) + "] (" + Format(trajectory.times[k - 1]) +
                         " s); give strictly increasing times");
        }
      }
      return trajectory;
    }
    case v1::Trajectory::KIND_NOT_SET:
      break;
  }
  check.Fail(field, "missing; give a sum_of_sines or a spline");
}

constexpr double kMinControlPeriod = 1e-6;      // s: 1 MHz, beyond any controller
constexpr double kMaxControlTimeout = 86400.0;  // s: a day

// A sampled drive's period_s (s): > 0 (>= 0 when `zero_allowed`: a continuous law).
double ControlPeriod(double period, const std::string& field, bool zero_allowed,
                     const Checker& check) {
  if (zero_allowed) {
    check.NonNegative(period, field, "s", "give the control period, or 0 for a continuous law");
    if (period == 0.0) return 0.0;
  } else {
    check.Positive(period, field, "s", "give the control period h, e.g. 0.001 for 1 kHz");
  }
  if (period < kMinControlPeriod) {
    check.Fail(field, "is " + Format(period) + " s, below " + Format(kMinControlPeriod) +
                          " s; give a control period of at least " + Format(kMinControlPeriod) +
                          " s");
  }
  return period;
}

DriveConfig ToDrive(const v1::Drive& spec, const std::string& field, const Checker& check) {
  DriveConfig drive;
  switch (spec.kind_case()) {
    case v1::Drive::kPassive:
      drive.kind = DriveConfig::Kind::kPassive;
      return drive;
    case v1::Drive::kPrescribed:
      drive.kind = DriveConfig::Kind::kPrescribed;
      drive.trajectory =
          ToTrajectory(spec.prescribed().trajectory(), field + ".prescribed.trajectory", check);
      drive.velocity_source = spec.prescribed().velocity_source();
      return drive;
    case v1::Drive::kTorque: {
      const std::string where = field + ".torque";
      const v1::Drive::Torque& torque = spec.torque();
      drive.kind = DriveConfig::Kind::kTorque;
      drive.constant = check.Finite(torque.constant(), where + ".constant", "N*m or N");
      drive.amplitude = check.Finite(torque.amplitude(), where + ".amplitude", "N*m or N");
      drive.omega = check.Finite(torque.omega(), where + ".omega", "rad/s");
      drive.phase = check.Finite(torque.phase(), where + ".phase", "rad");
      return drive;
    }
    case v1::Drive::kPdServo: {
      const std::string where = field + ".pd_servo";
      const v1::Drive::PdServo& servo = spec.pd_servo();
      drive.kind = DriveConfig::Kind::kPdServo;
      drive.kp = check.NonNegative(servo.kp(), where + ".kp", "N*m/rad or N/m",
                                   "give a non-negative stiffness gain");
      drive.kd = check.NonNegative(servo.kd(), where + ".kd", "N*m*s/rad or N*s/m",
                                   "give a non-negative damping gain");
      drive.trajectory = ToTrajectory(servo.trajectory(), where + ".trajectory", check);
      drive.period = ControlPeriod(servo.period_s(), where + ".period_s", true, check);
      return drive;
    }
    case v1::Drive::kExternal: {
      const std::string where = field + ".external";
      const v1::Drive::External& external = spec.external();
      drive.kind = DriveConfig::Kind::kExternal;
      const std::string& command = check.Name(external.command(), where + ".command");
      if (command.empty() || command == "effort") {
        drive.command = DriveConfig::Command::kEffort;
      } else if (command == "position") {
        drive.command = DriveConfig::Command::kPosition;
      } else if (command == "velocity") {
        drive.command = DriveConfig::Command::kVelocity;
      } else {
        check.Fail(where + ".command",
                   "is " + Quote(command) + "; give effort, position or velocity");
      }
      drive.period = ControlPeriod(external.period_s(), where + ".period_s", false, check);
      drive.kp = check.NonNegative(external.kp(), where + ".kp", "N*m/rad or N/m",
                                   "give a non-negative stiffness gain");
      drive.kd = check.NonNegative(external.kd(), where + ".kd", "N*m*s/rad or N*s/m",
                                   "give a non-negative damping gain");
      if (drive.command != DriveConfig::Command::kPosition && drive.kp != 0.0) {
        check.Fail(where + ".kp", "is " + Format(drive.kp) + " but command " +
                                      (command.empty() ? std::string("effort") : command) +
                                      " has no position error to act on; give kp only with "
                                      "command position");
      }
      if (drive.command == DriveConfig::Command::kEffort && drive.kd != 0.0) {
        check.Fail(where + ".kd", "is " + Format(drive.kd) +
                                      " but command effort applies the command as is; give kd "
                                      "only with command position or velocity");
      }
      return drive;
    }
    case v1::Drive::kPose:  // ToDrives reads it: it covers several coordinates
    case v1::Drive::KIND_NOT_SET:
      break;
  }
  check.Fail(field,
             "no drive kind; give one of prescribed, torque, pd_servo, external, pose or passive");
}

// The coordinates a pose drive (Drive.Pose) covers: a free joint NAME's six velocity
// coordinates NAME.vx .. NAME.wz, or a ball joint's three NAME.wx .wy .wz.
struct PoseJoint {
  int first = 0;  // index of the first velocity coordinate
  bool free = false;
};

std::optional<PoseJoint> FindPoseJoint(const std::string& name,
                                       const std::vector<std::string>& velocity_names) {
  const auto index = [&](const std::string& coordinate) {
    const auto at = std::find(velocity_names.begin(), velocity_names.end(), coordinate);
    return at == velocity_names.end() ? -1 : static_cast<int>(at - velocity_names.begin());
  };
  if (const int vx = index(name + ".vx"); vx >= 0) return PoseJoint{vx, true};
  if (const int wx = index(name + ".wx"); wx >= 0) return PoseJoint{wx, false};
  return std::nullopt;
}

// The free and ball joints' names, for a message.
std::vector<std::string> PoseJointNames(const std::vector<std::string>& velocity_names) {
  std::vector<std::string> names;
  for (const std::string& coordinate : velocity_names) {
    if (coordinate.size() > 3 && coordinate.compare(coordinate.size() - 3, 3, ".wx") == 0) {
      names.push_back(coordinate.substr(0, coordinate.size() - 3));
    }
  }
  return names;
}

// A pose drive's components, in the order of the joint's velocity coordinates: x y z roll
// pitch yaw (free), roll pitch yaw (ball); a component left out stays passive (DriveSet holds
// it at its initial value).
void ReadPose(const v1::Drive& spec, const PoseJoint& joint, const std::string& field,
              const Checker& check, DriveConfig* drives) {
  const v1::Drive::Pose& pose = spec.pose();
  const std::string where = field + ".pose";
  const std::pair<bool, const v1::Trajectory*> components[6] = {
      {pose.has_x(), &pose.x()},         {pose.has_y(), &pose.y()},
      {pose.has_z(), &pose.z()},         {pose.has_roll(), &pose.roll()},
      {pose.has_pitch(), &pose.pitch()}, {pose.has_yaw(), &pose.yaw()}};
  static constexpr const char* kNames[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
  if (!joint.free) {
    for (int k = 0; k < 3; ++k) {
      if (components[k].first) {
        check.Fail(where + "." + kNames[k],
                   "joint " + Quote(spec.joint()) +
                       " is a ball joint, which has no position; give roll, pitch and yaw only");
      }
    }
  }
  bool any = false;
  for (int k = joint.free ? 0 : 3; k < 6; ++k) {
    if (!components[k].first) continue;
    any = true;
    DriveConfig& drive = drives[joint.free ? k : k - 3];
    drive.kind = DriveConfig::Kind::kPrescribed;
    drive.trajectory = ToTrajectory(*components[k].second, where + "." + kNames[k], check);
  }
  if (!any) {
    check.Fail(where, std::string("has no component; give at least one of ") +
                          (joint.free ? "x, y, z, roll, pitch, yaw" : "roll, pitch, yaw") +
                          " (the others are held at their initial values)");
  }
}

std::vector<DriveConfig> ToDrives(const v1::RunSpec& spec,
                                  const std::vector<std::string>& joint_names,
                                  const Checker& check) {
  const int n = static_cast<int>(joint_names.size());
  // A drive that names a joint the model lacks says so first (a spec meant for another
  // model): that, not the count, is what to fix.
  for (int i = 0; i < spec.drives_size(); ++i) {
    const std::string& name = spec.drives(i).joint();
    if (spec.drives(i).has_pose()) continue;  // names a free or ball joint: checked below
    if (name.empty() ||
        std::find(joint_names.begin(), joint_names.end(), name) != joint_names.end()) {
      continue;
    }
    check.Name(name, "drives[" + std::to_string(i) + "].joint");
    check.Fail(
        "drives[" + std::to_string(i) + "].joint",
        "the model has no joint named " + Quote(name) + DidYouMean(name, joint_names) +
            "; give one of " + JoinNames(joint_names) +
            (spec.drives_size() > n ? " (is the spec meant for another model? it has " +
                                          std::to_string(spec.drives_size()) +
                                          " drives, the model " + std::to_string(n) + " joints)"
                                    : ""));
  }
  if (spec.drives_size() > n) {
    check.Fail("drives", "has " + std::to_string(spec.drives_size()) +
                             " drives but the model has " + std::to_string(n) + " joints (" +
                             JoinNames(joint_names) + "); give at most one drive per joint");
  }
  std::vector<DriveConfig> drives(n);  // passive unless a Drive says otherwise
  std::vector<std::optional<int>> driven_by(n);
  for (int i = 0; i < spec.drives_size(); ++i) {
    const v1::Drive& drive = spec.drives(i);
    const std::string field = "drives[" + std::to_string(i) + "]";
    if (drive.has_pose()) {
      if (check.Name(drive.joint(), field + ".joint").empty()) {
        check.Fail(field + ".joint", "is empty; a pose drive names its free or ball joint");
      }
      const std::optional<PoseJoint> pose_joint = FindPoseJoint(drive.joint(), joint_names);
      if (!pose_joint) {
        const std::vector<std::string> names = PoseJointNames(joint_names);
        check.Fail(field + ".joint", "the model has no free or ball joint named " +
                                         Quote(drive.joint()) + DidYouMean(drive.joint(), names) +
                                         "; a pose drive takes one of " + JoinNames(names) +
                                         " (a one-coordinate joint takes a prescribed drive)");
      }
      const int count = pose_joint->free ? 6 : 3;
      for (int k = pose_joint->first; k < pose_joint->first + count; ++k) {
        if (driven_by[k]) {
          check.Fail(field, "joint '" + drive.joint() + "' already has a drive (drives[" +
                                std::to_string(*driven_by[k]) + "], on " + joint_names[k] +
                                "); give each joint at most one drive");
        }
        driven_by[k] = i;
      }
      ReadPose(drive, *pose_joint, field, check, drives.data() + pose_joint->first);
      continue;
    }
    int joint = i;
    if (!check.Name(drive.joint(), field + ".joint").empty()) {
      joint = 0;
      while (joint < n && joint_names[joint] != drive.joint()) ++joint;
      if (joint == n) {
        check.Fail(field + ".joint", "the model has no joint named " + Quote(drive.joint()) +
                                         DidYouMean(drive.joint(), joint_names) + "; give one of " +
                                         JoinNames(joint_names));
      }
    }
    if (driven_by[joint]) {
      check.Fail(field, "joint '" + joint_names[joint] + "' already has a drive (drives[" +
                            std::to_string(*driven_by[joint]) +
                            "]); give each joint at most one drive");
    }
    driven_by[joint] = i;
    drives[joint] = ToDrive(drive, field, check);
  }
  // One control period per run: the sampled drives share their control instants.
  std::optional<int> first_sampled;
  for (int j = 0; j < n; ++j) {
    if (drives[j].period <= 0.0) continue;
    if (!first_sampled) {
      first_sampled = j;
    } else if (drives[j].period != drives[*first_sampled].period) {
      const auto kind = [&](int joint) {
        return std::string(drives[joint].kind == DriveConfig::Kind::kExternal ? "external"
                                                                              : "pd_servo");
      };
      check.Fail("drives[" + std::to_string(*driven_by[j]) + "]." + kind(j) + ".period_s",
                 "is " + Format(drives[j].period) + " s but drives[" +
                     std::to_string(*driven_by[*first_sampled]) + "]." + kind(*first_sampled) +
                     ".period_s is " + Format(drives[*first_sampled].period) +
                     " s; give every sampled drive of a run the same control period");
    }
  }
  return drives;
}

// duration_s, output_interval_s, max_step_s.
void ReadTimes(const v1::RunSpec& spec, const Checker& check, RunConfig* config) {
  if (spec.has_duration_s()) {
    config->duration = check.Positive(spec.duration_s(), "duration_s", "s",
                                      "give the simulated time span, e.g. 20");
    if (config->duration > kMaxDuration) {
      check.Fail("duration_s", "is " + Format(config->duration) + " s, more than " +
                                   Format(kMaxDuration) + " s; give a shorter span");
    }
  }
  if (spec.has_output_interval_s()) {
    config->output_interval = check.Positive(spec.output_interval_s(), "output_interval_s", "s",
                                             "give the time between output frames, e.g. 0.05");
  }
  if (config->output_interval > config->duration) {
    check.Fail("output_interval_s",
               Format(config->output_interval) + " s is longer than duration_s (" +
                   Format(config->duration) + " s); give an interval no longer than the duration");
  }
  if (config->duration / config->output_interval > kMaxFrames) {
    check.Fail("output_interval_s", Format(config->output_interval) + " s over duration_s " +
                                        Format(config->duration) + " s gives more than " +
                                        Format(kMaxFrames) + " frames; give a longer interval");
  }
  if (spec.has_max_step_s()) {
    config->max_step = check.NonNegative(spec.max_step_s(), "max_step_s", "s",
                                         "give the largest internal step, or 0 for no limit");
    if (config->max_step > 0.0 && config->max_step < kMinStep) {
      check.Fail("max_step_s", "is " + Format(config->max_step) + " s, below the smallest " +
                                   "step mbstream takes (" + Format(kMinStep) +
                                   " s); give 0 for no limit or a step of at least that");
    }
  }
}

// formulation, method, erk_table, rtol, atol, fixed_step_s.
void ReadSolver(const v1::RunSpec& spec, const Checker& check, RunConfig* config) {
  if (!spec.formulation().empty() && !ParseFormulation(spec.formulation(), &config->formulation)) {
    check.Fail("formulation",
               "unknown name " + Quote(spec.formulation()) + "; give one of " + FormulationNames());
  }
  if (spec.method() == "auto") {
    config->method_auto = true;
  } else if (!spec.method().empty() && !ParseMethod(spec.method(), &config->method)) {
    check.Fail("method", "unknown name " + Quote(spec.method()) + "; give one of " + MethodNames() +
                             ", or auto with a target");
  }
  config->erk_table = check.Name(spec.erk_table(), "erk_table");
  if (spec.has_rtol()) {
    config->rtol = check.Tolerance(spec.rtol(), "rtol", "give a relative tolerance, e.g. 1e-6");
  }
  if (spec.has_atol()) {
    config->atol = check.Tolerance(spec.atol(), "atol", "give an absolute tolerance, e.g. 1e-8");
  }
  if (spec.has_fixed_step_s()) {
    config->fixed_step = check.Finite(spec.fixed_step_s(), "fixed_step_s", "s");
    if ((config->method == Method::kRk4 || config->method == Method::kEuler) &&
        !(config->fixed_step > 0.0)) {
      check.Fail("fixed_step_s", std::string("must be > 0 (s) for method ") +
                                     MethodName(config->method) + ", got " +
                                     Format(config->fixed_step) + "; give the step, e.g. 0.001");
    }
    if (config->fixed_step > 0.0 && config->fixed_step < kMinStep) {
      check.Fail("fixed_step_s", "is " + Format(config->fixed_step) + " s, below the smallest " +
                                     "step mbstream takes (" + Format(kMinStep) +
                                     " s); give a larger step, e.g. 0.001");
    }
  }
}

// gravity, initial state (initial_q, initial_qd, initial_bodies), drives, torques, Baumgarte
// gains.
void ReadPhysics(const v1::RunSpec& spec, const SpecCoordinates& coordinates, const Checker& check,
                 const std::string& source, RunConfig* config) {
  const std::vector<std::string>& joint_names = coordinates.velocities;
  const bool free = coordinates.positions.size() != coordinates.velocities.size();
  if (spec.has_gravity()) {
    config->gravity = {check.Finite(spec.gravity().x(), "gravity.x", "m/s^2"),
                       check.Finite(spec.gravity().y(), "gravity.y", "m/s^2"),
                       check.Finite(spec.gravity().z(), "gravity.z", "m/s^2")};
    for (int axis = 0; axis < 3; ++axis) {
      if (std::abs(config->gravity[axis]) > kMaxGravity) {
        check.Fail(std::string("gravity.") + "xyz"[axis],
                   "is " + Format(config->gravity[axis]) + " m/s^2, beyond +-" +
                       Format(kMaxGravity) + " m/s^2 (1,000 g); give the gravity in m/s^2, " +
                       "e.g. z = -9.81");
      }
    }
  }
  config->q0 =
      JointVector(spec.initial_q(), coordinates.positions, free ? "position coordinates" : "joints",
                  "initial_q", free ? "rad, m or a quaternion's components" : kJointUnit, check);
  config->qd0 =
      JointVector(spec.initial_qd(), joint_names, free ? "velocity coordinates" : "joints",
                  "initial_qd", "rad/s or m/s", check);
  config->initial_bodies = ToInitialBodies(spec.initial_bodies(), coordinates.positions, source);
  config->drives = ToDrives(spec, joint_names, check);
  config->want_torques = spec.has_want_torques() ? spec.want_torques() : true;
  config->want_loop_forces = spec.report_loop_forces();
  if (spec.has_baumgarte()) {
    const v1::Baumgarte& baumgarte = spec.baumgarte();
    if (baumgarte.has_alpha()) {
      config->baumgarte.alpha = check.NonNegative(baumgarte.alpha(), "baumgarte.alpha", "1/s",
                                                  "give a non-negative feedback gain, e.g. 10");
    }
    if (baumgarte.has_beta()) {
      config->baumgarte.beta = check.NonNegative(baumgarte.beta(), "baumgarte.beta", "1/s^2",
                                                 "give a non-negative feedback gain, e.g. 25");
    }
  }
}

// max_internal_steps, max_cpu_s.
void ReadBudget(const v1::RunSpec& spec, const Checker& check, RunConfig* config) {
  if (spec.has_max_internal_steps()) {
    if (spec.max_internal_steps() <= 0) {
      check.Fail("max_internal_steps", "must be > 0, got " +
                                           std::to_string(spec.max_internal_steps()) +
                                           "; give the most internal steps, e.g. 10000000, "
                                           "or leave it out for the default budget");
    }
    config->max_steps = spec.max_internal_steps();
  }
  if (spec.has_max_cpu_s()) {
    config->max_cpu_s =
        check.Positive(spec.max_cpu_s(), "max_cpu_s", "s of CPU",
                       "give the most CPU seconds the run may use, e.g. 60, or leave it out "
                       "for the default budget");
  }
}

// target, method auto, verify.
void ReadTarget(const v1::RunSpec& spec, const Checker& check, RunConfig* config) {
  if (spec.has_target()) {
    const v1::Target& target = spec.target();
    const std::string advice =
        "give the largest error the run may have, e.g. 1e-5, or leave it out";
    if (target.has_tcp_error_m()) {
      config->target.tcp_error_m =
          check.Positive(target.tcp_error_m(), "target.tcp_error_m", "m", advice);
    }
    if (target.has_joint_error_rad()) {
      config->target.joint_error_rad =
          check.Positive(target.joint_error_rad(), "target.joint_error_rad", "rad", advice);
    }
    if (target.has_energy_error_rel()) {
      config->target.energy_error_rel =
          check.Positive(target.energy_error_rel(), "target.energy_error_rel", "relative", advice);
    }
    if (!config->target.any()) {
      check.Fail("target", "is empty; give tcp_error_m, joint_error_rad or energy_error_rel");
    }
    if (spec.method().empty()) config->method_auto = true;
  }
  if (config->method_auto && !config->target.any()) {
    check.Fail("method",
               "auto chooses the method for an accuracy target, and the spec has none; "
               "give target.tcp_error_m (or joint_error_rad, energy_error_rel), or a "
               "method");
  }
  config->verify = spec.has_verify() ? spec.verify() : true;
}

// keep.
void ReadKeep(const v1::RunSpec& spec, const Checker& check, RunConfig* config) {
  std::string why;
  if (!ParseFrameKeep(spec.keep(), &config->keep, &why)) {
    check.Fail("keep", "is \"" + spec.keep().substr(0, 64) + "\"; " + why);
  }
}

// sensor_points: their shape (names, offsets); their links are the model's (ValidateRun).
constexpr int kMaxSensorPoints = 64;
constexpr double kMaxSensorOffset = 1e3;  // m from its link's origin: beyond any mechanism

void ReadSensorPoints(const v1::RunSpec& spec, const Checker& check, RunConfig* config) {
  check.Count(spec.sensor_points_size(), kMaxSensorPoints, "sensor_points",
              "give the points your controller reads");
  for (int i = 0; i < spec.sensor_points_size(); ++i) {
    const v1::SensorPoint& point = spec.sensor_points(i);
    const std::string field = "sensor_points[" + std::to_string(i) + "]";
    SensorPointConfig sensor;
    sensor.link = check.Name(point.link(), field + ".link");
    if (sensor.link.empty()) {
      check.Fail(field + ".link", "is empty; give the name of the link the point is fixed on");
    }
    sensor.name = check.Name(point.name().empty() ? point.link() : point.name(), field + ".name");
    const double offset[3] = {point.offset_m().x(), point.offset_m().y(), point.offset_m().z()};
    for (int axis = 0; axis < 3; ++axis) {
      const std::string component = field + ".offset_m." + "xyz"[axis];
      sensor.offset[axis] = check.Finite(offset[axis], component, "m");
      if (std::abs(offset[axis]) > kMaxSensorOffset) {
        check.Fail(component, "is " + Format(offset[axis]) + " m, beyond +-" +
                                  Format(kMaxSensorOffset) +
                                  " m; give the point in its link's frame, in m");
      }
    }
    for (const SensorPointConfig& other : config->sensor_points) {
      if (other.name == sensor.name) {
        check.Fail(field + ".name", Quote(sensor.name) +
                                        " names another sensor point already; give each "
                                        "point its own name");
      }
    }
    config->sensor_points.push_back(std::move(sensor));
  }
}

// The fields only the server acts on (realtime, retries, max_output_frames): checked here so
// that simulate refuses what the server refuses; not part of RunConfig.
void CheckServerFields(const v1::RunSpec& spec, const Checker& check) {
  check.NonNegative(spec.realtime(), "realtime", "simulated s per wall-clock s",
                    "give 0 for as fast as possible or 1 for real time");
  if (spec.realtime() != 0.0 &&
      !(spec.realtime() >= kMinRealtime && spec.realtime() <= kMaxRealtime)) {
    check.Fail("realtime", "is " + Format(spec.realtime()) +
                               "; give 0 (as fast as possible) or a "
                               "factor from " +
                               Format(kMinRealtime) + " to " + Format(kMaxRealtime) +
                               " (1 = real time)");
  }
  if (spec.retries() < 0 || spec.retries() > kMaxRetries) {
    check.Fail("retries", "is " + std::to_string(spec.retries()) + "; give 0 (never run again) " +
                              "to " + std::to_string(kMaxRetries) + " attempts after the first");
  }
  if (spec.has_control_timeout_s()) {
    check.Positive(spec.control_timeout_s(), "control_timeout_s", "s",
                   "give how long the run waits for its controller, e.g. 10");
    if (spec.control_timeout_s() > kMaxControlTimeout) {
      check.Fail("control_timeout_s", "is " + Format(spec.control_timeout_s()) + " s, more than " +
                                          Format(kMaxControlTimeout) +
                                          " s (a day); give a shorter wait");
    }
  }
  if (spec.max_output_frames() < 0) {
    check.Fail("max_output_frames", "must be >= 0, got " +
                                        std::to_string(spec.max_output_frames()) +
                                        "; give 0 for the server's limit");
  }
}

}  // namespace

RunConfig ToRunConfig(const v1::RunSpec& spec, const std::vector<std::string>& joint_names,
                      const std::string& source) {
  return ToRunConfig(spec, SpecCoordinates{joint_names, joint_names}, source);
}

RunConfig ToRunConfig(const v1::RunSpec& spec, const SpecCoordinates& coordinates,
                      const std::string& source) {
  const Checker check(source);
  if (const size_t bytes = spec.ByteSizeLong(); bytes > kMaxSpecBytes) {
    check.Fail("(spec)", "is " + std::to_string(bytes) + " bytes encoded, more than " +
                             std::to_string(kMaxSpecBytes) + "; give fewer or shorter fields");
  }
  RunConfig config;
  ReadTimes(spec, check, &config);
  ReadSolver(spec, check, &config);
  ReadPhysics(spec, coordinates, check, source, &config);
  ReadBudget(spec, check, &config);
  ReadTarget(spec, check, &config);
  ReadKeep(spec, check, &config);
  ReadSensorPoints(spec, check, &config);
  if (spec.has_contact()) config.contact = ToContactSettings(spec.contact(), source);
  CheckServerFields(spec, check);
  return config;
}

}  // namespace mbstream
