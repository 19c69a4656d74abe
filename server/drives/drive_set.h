// The drives of a run, joint by joint: reference motions and applied efforts.
#pragma once

#include <vector>

#include "server/drives/drive_config.h"
#include "server/drives/trajectory.h"
#include "server/model/model.h"

namespace mbstream {

class DriveSet {
 public:
  // `drives` has one entry per joint (server/spec guarantees it; checked).
  DriveSet(const Model& model, const std::vector<DriveConfig>& drives);

  int size() const { return static_cast<int>(drives_.size()); }
  DriveConfig::Kind kind(int joint) const { return drives_[joint].kind; }
  bool prescribed(int joint) const { return kind(joint) == DriveConfig::Kind::kPrescribed; }
  // Prescribed by velocity (q integrated from qd_ref), the seed's drive.
  bool velocity_source(int joint) const {
    return prescribed(joint) && drives_[joint].velocity_source;
  }
  int num_prescribed() const { return num_prescribed_; }
  bool all_prescribed() const { return num_prescribed_ == size(); }
  // True when some drive or damping does work (energy is then not conserved).
  bool any_work() const { return any_work_; }

  // Reference motion of a prescribed or servo joint at time t (s).
  TrajectoryPoint Reference(int joint, double t) const { return references_[joint].At(t); }

  // Effort of the actuator of a non-prescribed joint at (t, q, qd): the torque law or the
  // servo law, zero for passive joints (N*m or N). Damping is not included.
  double ActuatorEffort(int joint, double t, double q, double qd) const;

  // Scratch of ActuatorEfforts: sin and cos of each distinct sine argument at one time. The
  // caller owns it (one per run, e.g. the run's ODE), so that a DriveSet stays const and
  // shareable between threads. Only for the DriveSet that made it.
  struct Workspace {
    const DriveSet* owner = nullptr;
    std::vector<double> sin, cos;
  };
  Workspace MakeWorkspace() const;  // allocates: once per run

  // ActuatorEffort of every joint at (t, q, qd) into `effort` (0 for passive and prescribed
  // joints): q, qd and effort are arrays of size() (rad or m, rad/s or m/s; N*m or N). Bit
  // for bit the values of ActuatorEffort, but each distinct (omega, phase) of the servos'
  // sum-of-sines references and of the torque laws takes one sincos(omega * t + phase) per
  // call, however many joints share it. Allocates nothing.
  void ActuatorEfforts(double t, const double* q, const double* qd, Workspace& workspace,
                       double* effort) const;
  // How many sincos ActuatorEfforts evaluates: the distinct (omega, phase) pairs.
  int num_sine_arguments() const { return static_cast<int>(arguments_.size()); }

  // The joint's viscous damping coefficient (N*m*s/rad or N*s/m).
  double damping(int joint) const { return damping_[joint]; }

 private:
  // Joint's effort given how the sine and cosine of each of its terms' arguments are found.
  template <typename SinCos>
  double LawEffort(int joint, double t, double q, double qd, SinCos&& sin_cos) const;

  std::vector<DriveConfig> drives_;
  std::vector<TrajectoryEvaluator> references_;
  std::vector<double> damping_;
  // For ActuatorEfforts: the distinct sine arguments omega * t + phase (rad/s, rad), the
  // sine terms, and each joint's law in compact form.
  struct SineArgument {
    double omega, phase;
  };
  struct SineTerm {
    int argument;            // index into arguments_
    double amplitude;        // a (rad or m; N*m or N for a torque law)
    double amplitude_omega;  // a * omega, the factor of cos in qd_ref (rad/s or m/s)
  };
  struct EffortLaw {
    DriveConfig::Kind kind;
    bool spline_reference = false;     // servo: reference from references_ (else sum of sines)
    int first_term = 0, end_term = 0;  // the law's terms: terms_[first_term, end_term)
    // Servo: the reference's offset (rad or m); torque law: its constant (N*m or N).
    double base = 0.0;
    double kp = 0.0, kd = 0.0;  // servo gains
  };
  std::vector<SineArgument> arguments_;
  std::vector<SineTerm> terms_;
  std::vector<EffortLaw> laws_;  // one per joint
  int num_prescribed_ = 0;
  bool any_work_ = false;
};

// The indices of the prescribed joints of `drives`, in joint order.
std::vector<int> PrescribedJoints(const DriveSet& drives);

}  // namespace mbstream
