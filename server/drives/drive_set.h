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
  // A prescribed pose (pose_motion.h): a free or ball joint with a prescribed drive on some of
  // its velocity coordinates (its pose's components x y z roll pitch yaw, or a ball joint's
  // roll pitch yaw, in order) has all of them prescribed; the ones without a drive are held at
  // their initial value, and pose_hold is true for them (their Reference is 0).
  bool pose_hold(int joint) const { return pose_hold_[joint] != 0; }
  // The bodies whose free or ball joint has a prescribed pose, ascending.
  const std::vector<int>& posed_bodies() const { return posed_bodies_; }
  bool all_prescribed() const { return num_prescribed_ == size(); }
  // True when some drive or damping does work (energy is then not conserved).
  bool any_work() const { return any_work_; }
  // Sampled drives (zero-order hold over a control period): external ones and pd_servos
  // with a period. Their effort between control instants comes from the value held in the
  // Workspace (SampleServos, or the controller's command for an external drive).
  bool sampled(int joint) const { return held_[joint] != Held::kNone; }
  bool any_sampled() const { return !sampled_.empty(); }
  const std::vector<int>& sampled_joints() const { return sampled_; }
  const std::vector<int>& external_joints() const { return external_; }
  // s, the control period of the sampled drives (validation makes them share one); 0: none.
  double control_period() const { return period_; }

  // Reference motion of a prescribed or servo joint at time t (s).
  TrajectoryPoint Reference(int joint, double t) const { return references_[joint].At(t); }

  // Effort of the actuator of a non-prescribed joint at (t, q, qd): the torque law or the
  // servo law, zero for passive joints (N*m or N). Damping is not included. A sampled joint's
  // with a held value of 0 (its slopes in q and qd are the held law's).
  double ActuatorEffort(int joint, double t, double q, double qd) const;

  // Scratch of ActuatorEfforts: sin and cos of each distinct sine argument at one time. The
  // caller owns it (one per run, e.g. the run's ODE), so that a DriveSet stays const and
  // shareable between threads. Only for the DriveSet that made it.
  struct Workspace {
    const DriveSet* owner = nullptr;
    std::vector<double> sin, cos;
    // Per joint, a sampled drive's held value since the last control instant: a sampled
    // servo's effort or an external drive's command (N*m or N, rad or m, rad/s or m/s).
    std::vector<double> held;
  };
  Workspace MakeWorkspace() const;  // allocates: once per run

  // ActuatorEffort of every joint at (t, q, qd) into `effort` (0 for passive and prescribed
  // joints): q, qd and effort are arrays of size() (rad or m, rad/s or m/s; N*m or N). Bit
  // for bit the values of ActuatorEffort, but each distinct (omega, phase) of the servos'
  // sum-of-sines references and of the torque laws takes one sincos(omega * t + phase) per
  // call, however many joints share it. Allocates nothing.
  void ActuatorEfforts(double t, const double* q, const double* qd, Workspace& workspace,
                       double* effort) const;
  // At a control instant t: each sampled pd_servo's law at (t, q, qd) into workspace.held,
  // held until the next instant. Allocates nothing.
  void SampleServos(double t, const double* q, const double* qd, Workspace& workspace) const;
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
  std::vector<unsigned char> pose_hold_;  // one per joint (pose_hold)
  std::vector<int> posed_bodies_;
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
  // How a joint's effort follows from its held value (kNone: not sampled).
  enum class Held { kNone, kEffort, kPosition, kVelocity };
  double HeldEffort(int joint, double q, double qd, double held) const;
  std::vector<Held> held_;        // one per joint
  std::vector<int> sampled_;      // the sampled joints, in joint order
  std::vector<int> external_;     // the external joints, in joint order
  std::vector<int> servos_held_;  // the sampled pd_servos, in joint order
  double period_ = 0.0;
  int num_prescribed_ = 0;
  bool any_work_ = false;
};

// The indices of the prescribed joints of `drives`, in joint order.
std::vector<int> PrescribedJoints(const DriveSet& drives);

}  // namespace mbstream
