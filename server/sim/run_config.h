// What a run asks for, as the physics core sees it: a plain value (copyable, comparable),
// with no generated (protobuf) code and no live state (a pilot's state travels beside it:
// PilotLink, run_prefix.h). The service and the CLI convert the wire/JSON RunSpec into this at
// their edge (server/spec/) and validate it there, once (ValidateRun, run_validation.h).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "server/body/baumgarte_parameters.h"
#include "server/contact/contact_settings.h"
#include "server/drives/drive_config.h"
#include "server/integrate/method.h"
#include "server/sim/frame_keep.h"
#include "server/sim/initial_bodies.h"

namespace mbstream {

// A point fixed on a link whose world position a controlled run's states carry
// (RunSpec.sensor_points, ControlState::sensors).
struct SensorPointConfig {
  std::string name;  // unique among the run's points
  std::string link;  // a link (or frame) of the model, by name (ValidateRun)
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // m, in the link's frame
  bool operator==(const SensorPointConfig&) const = default;
};

// How the mechanism is modelled ("model no more than a scene needs").
enum class Formulation {
  kAuto,           // the least formulation that answers the run's outputs
  kKinematic,      // every joint prescribed, no forces asked for: closed form, no integration
  kJoint,          // minimal coordinates, ODE of 2n states
  kBodyIndex3,     // body coordinates, position-level constraints (DAE, IDA)
  kBodyIndex2,     // body coordinates, velocity-level constraints (DAE, IDA)
  kBodyBaumgarte,  // body coordinates, stabilised acceleration-level constraints (ODE)
};

// An accuracy the run must reach, instead of (or besides) a method and tolerances: the
// server chooses them (server/choose/). 0 = not asked.
struct AccuracyTarget {
  double tcp_error_m = 0.0;       // m, largest TCP error over the output frames
  double joint_error_rad = 0.0;   // rad (m for prismatic joints), largest joint error
  double energy_error_rel = 0.0;  // relative energy-balance error (RunStats::energy_error_max)

  bool any() const { return tcp_error_m > 0.0 || joint_error_rad > 0.0 || energy_error_rel > 0.0; }
  bool operator==(const AccuracyTarget&) const = default;
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
  bool want_loop_forces = false;    // report the cut joints' reactions (RunResult::loop_forces)
  BaumgarteParameters baumgarte;
  // The run's cost budget (see run_budget.h); the run stops with TOO_MUCH_WORK when either
  // runs out. 0 = the default for the run's duration and model (DefaultMaxSteps,
  // DefaultMaxCpuSeconds).
  long max_steps = 0;      // internal integrator steps
  double max_cpu_s = 0.0;  // s of CPU time of the run's thread
  // The accuracy target (none by default). With method_auto the server chooses the method
  // and tolerances for it; with a method given, only the tolerances.
  AccuracyTarget target;
  bool method_auto = false;  // method "auto": chosen for the target (needs one)
  bool verify = true;        // check the achieved error after a target run
  FrameKeep keep;            // which output frames the run keeps (the engine drops the rest)
  ContactSettings contact;   // contact forces (joint formulation; docs/contact.md)
  // Points whose world positions a controlled run's states carry (external drives only).
  std::vector<SensorPointConfig> sensor_points;
  // Free bodies' initial poses and twists by name, over q0 and qd0 (initial_bodies.h).
  std::vector<InitialBodyState> initial_bodies;

  // Field by field, exactly (doubles bit for bit but for -0 == 0; q0 and qd0 of another
  // size differ).
  bool operator==(const RunConfig& other) const;
};

const char* FormulationName(Formulation formulation);  // "auto", "kinematic", "joint", ...
// Parses the name of the contract; returns false for an unknown name.
bool ParseFormulation(const std::string& name, Formulation* formulation);

}  // namespace mbstream
