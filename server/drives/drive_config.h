// What drives each joint, as a run asks for it: reference motions and actuator laws.
#pragma once

#include <vector>

namespace mbstream {

// q(t) for one joint (rad or m; t in s).
struct Trajectory {
  enum class Kind {
    kSine,    // q = offset + sum_k amplitude[k] * sin(omega[k] * t + phase[k])
    kSpline,  // natural cubic spline through (times[k], values[k]), held constant outside
  };
  Kind kind = Kind::kSine;
  double offset = 0.0;
  std::vector<double> amplitude, omega, phase;  // rad or m, rad/s, rad
  std::vector<double> times, values;            // s, rad or m (strictly increasing times)
  bool operator==(const Trajectory&) const = default;
};

// What drives one joint.
struct DriveConfig {
  enum class Kind {
    kPassive,     // no actuator: only the joint's damping acts
    kPrescribed,  // motion imposed by `trajectory`; dynamics then yields the drive effort
    kTorque,      // applied effort: constant + amplitude * sin(omega * t + phase) (N*m or N)
    kPdServo,     // effort = kp (q_ref - q) + kd (qd_ref - qd), q_ref from `trajectory`
    kExternal,    // a controller outside the engine commands it (ControlLaw, control_law.h)
  };
  // kExternal: what the controller's command is, held over each period. kEffort: the effort
  // itself (N*m or N); kPosition: a setpoint q* (rad or m) of the server's PD, effort =
  // kp (q* - q) - kd qd; kVelocity: a setpoint qd* (rad/s or m/s), effort = kd (qd* - qd).
  enum class Command { kEffort, kPosition, kVelocity };
  Kind kind = Kind::kPassive;
  Trajectory trajectory;  // kPrescribed and kPdServo
  // kPrescribed only: the seed's velocity-source drive. The drive imposes qd(t) and the
  // formulation integrates q from it (instead of imposing q(t) in closed form).
  bool velocity_source = false;
  // s, the control period h of a sampled drive: kExternal (> 0) and kPdServo (0 = the law
  // acts continuously; > 0: its effort is computed at t_k = k h from the state then and held
  // over [t_k, t_k+1), a zero-order hold).
  double period = 0.0;
  Command command = Command::kEffort;  // kExternal
  double kp = 0.0;                     // N*m/rad or N/m
  double kd = 0.0;                     // N*m*s/rad or N*s/m
  double constant = 0.0;               // kTorque
  double amplitude = 0.0;              // kTorque
  double omega = 0.0;                  // kTorque, rad/s
  double phase = 0.0;                  // kTorque, rad
  bool operator==(const DriveConfig&) const = default;
};

}  // namespace mbstream
