// What a run asks for, as the physics core sees it: a plain struct, with no generated
// (protobuf) code. The service and the CLI convert the wire/JSON RunSpec into this at their
// edge (server/spec/), validating it there.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace mbstream {

// How the mechanism is modelled ("model no more than a scene needs").
enum class Formulation {
  kAuto,           // the least formulation that answers the run's outputs
  kKinematic,      // every joint prescribed, no forces asked for: closed form, no integration
  kJoint,          // minimal coordinates, ODE of 2n states
  kBodyIndex3,     // body coordinates, position-level constraints (DAE, IDA)
  kBodyIndex2,     // body coordinates, velocity-level constraints (DAE, IDA)
  kBodyBaumgarte,  // body coordinates, stabilised acceleration-level constraints (ODE)
};

// The time integrator.
enum class Method {
  kBdf,    // CVODE BDF (variable order 1-5), Newton with dense Jacobian
  kAdams,  // CVODE Adams-Moulton (orders 1-12), functional iteration
  kErk,    // ARKODE explicit Runge-Kutta (table in RunConfig::erk_table)
  kDirk,   // ARKODE diagonally implicit Runge-Kutta
  kIda,    // IDA (DAE formulations)
  kRk4,    // fixed-step classical Runge-Kutta 4
  kEuler,  // fixed-step semi-implicit (symplectic) Euler, the game-engine baseline
};

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
};

// What drives one joint.
struct DriveConfig {
  enum class Kind {
    kPassive,     // no actuator: only the joint's damping acts
    kPrescribed,  // motion imposed by `trajectory`; dynamics then yields the drive effort
    kTorque,      // applied effort: constant + amplitude * sin(omega * t + phase) (N*m or N)
    kPdServo,     // effort = kp (q_ref - q) + kd (qd_ref - qd), q_ref from `trajectory`
  };
  Kind kind = Kind::kPassive;
  Trajectory trajectory;  // kPrescribed and kPdServo
  // kPrescribed only: the seed's velocity-source drive. The drive imposes qd(t) and the
  // formulation integrates q from it (instead of imposing q(t) in closed form).
  bool velocity_source = false;
  double kp = 0.0;         // N*m/rad or N/m
  double kd = 0.0;         // N*m*s/rad or N*s/m
  double constant = 0.0;   // kTorque
  double amplitude = 0.0;  // kTorque
  double omega = 0.0;      // kTorque, rad/s
  double phase = 0.0;      // kTorque, rad
};

struct BaumgarteParameters {
  double alpha = 10.0;  // 1/s, velocity-error feedback
  double beta = 25.0;   // 1/s^2, position-error feedback
};

struct RunConfig {
  double duration = 20.0;         // s
  double output_interval = 0.05;  // s between output frames (first frame at t = 0)
  double max_step = 0.0;          // s, largest internal step; 0 = no limit
  Formulation formulation = Formulation::kAuto;
  Method method = Method::kBdf;
  std::string erk_table;  // ARKODE table name for kErk ("" = default order-4/5)
  double rtol = 1e-6;
  double atol = 1e-8;
  double fixed_step = 1e-3;                  // s, for kRk4 and kEuler
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};  // m/s^2, base frame
  Eigen::VectorXd q0;                        // initial joint positions (empty = zeros / trajectory)
  Eigen::VectorXd qd0;              // initial joint velocities (empty = zeros / trajectory)
  std::vector<DriveConfig> drives;  // one per joint, in the model's joint order
  bool want_torques = true;         // report drive efforts (needs dynamics)
  BaumgarteParameters baumgarte;
  // The run's cost budget (see run_budget.h); the run stops with TOO_MUCH_WORK when either
  // runs out. 0 = the default for the run's duration and model (DefaultMaxSteps,
  // DefaultMaxCpuSeconds).
  long max_steps = 0;      // internal integrator steps
  double max_cpu_s = 0.0;  // s of CPU time of the run's thread
};

const char* FormulationName(Formulation formulation);  // "auto", "kinematic", "joint", ...
const char* MethodName(Method method);                 // "bdf", "adams", ...
// Parse the names of the contract; return false for an unknown name.
bool ParseFormulation(const std::string& name, Formulation* formulation);
bool ParseMethod(const std::string& name, Method* method);

}  // namespace mbstream
