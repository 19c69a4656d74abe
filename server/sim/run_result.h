// What a run produces: output frames, statistics, accuracy figures and its status.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "server/integrate/integrator.h"
#include "server/sim/contact_log.h"
#include "server/sim/run_summary.h"

namespace mbstream {

struct JointIntegration;  // joint_integration.h

// RunStats::energy_work.
inline constexpr char kEnergyWorkNone[] = "none: no drive or damping does work";
inline constexpr char kEnergyWorkIntegrated[] =
    "integrated: a quadrature of the ODE, advanced with its states by the run's method "
    "outside the error control";
inline constexpr char kEnergyWorkTrapezoid[] =
    "trapezoid: the trapezoid rule over the output frames (an approximation of its own)";

enum class RunStatus {
  kFinished,
  kDiverged,             // the state became non-finite or exploded; stopped at the last good time
  kTooMuchWork,          // the cost budget (internal steps or CPU seconds) ran out
  kErrorTestFailures,    // the integrator could not meet the tolerance
  kConvergenceFailures,  // the nonlinear/linear solver failed repeatedly
  kFailed,               // any other failure (see the message)
  kCancelled,
  kInterrupted,  // the server stopped during the run (never produced by Simulate itself)
};

// Whether a run's own error indicators say its result can be trusted (run_trust.h).
enum class Trust {
  kNotAssessed,  // the run did not finish: its status says what went wrong
  kOk,
  kLow,  // finished, but the energy balance, constraint drift or step statistics say the
         // result cannot be trusted (RunStats::trust_reason says which and by how much)
};

// "", "ok", "low".
const char* TrustName(Trust trust);

// "FINISHED", "DIVERGED", "TOO_MUCH_WORK", ...
const char* RunStatusName(RunStatus status);

// The run status of an integrator's failure (kOk -> kFinished).
RunStatus ToRunStatus(IntegratorStatus status);

// A mechanism with closed loops: how they were closed (RunStats::loops; no cut joints for a
// tree). The constraint residuals are RunStats' drift figures.
struct LoopStats {
  std::vector<std::string> cut_joints;  // "NAME (TYPE)": the joints cut to leave the tree
  int equations = 0;                    // the cut joints' constraint equations
  int independent = 0;                  // their rank: the rest are redundant
  int mobility = 0;                     // the mechanism's degrees of freedom
  std::string assembly;                 // how the initial pose was assembled
};

struct RunStats {
  RunStatus status = RunStatus::kFinished;
  std::string message;     // on failure: what happened and what to try
  double t_reached = 0.0;  // s, simulated time of the last good frame

  std::string formulation;  // "kinematic", "joint", ...
  std::string formulation_reason;
  int equations = 0;       // states (ODE) or equations (DAE); 0 when nothing integrates
  int jacobian_nnz = 0;    // structural non-zeros of the iteration Jacobian
  std::string method;      // "bdf", ... or "none"
  std::string integrator;  // e.g. "CVODE BDF"
  SolverStats solver;
  double cpu_s = 0.0;  // CPU time of the run's thread
  // s: the run took its frames up to this time from a pilot's (PilotLink::prefix) and went
  // on with the pilot's integration from there; `solver` counts its own steps only. 0: it
  // integrated from t = 0.
  double continued_from_s = 0.0;
  double wall_s = 0.0;

  // Accuracy, where a reference exists (negative = no reference).
  double tcp_error_max = -1.0;     // m, TCP against direct kinematics of the prescribed motion
  double energy_error_max = -1.0;  // relative energy-balance error over the run
  bool energy_work_approximate = false;  // work of drives/damping integrated from outputs
  // With energy_work_approximate: the trapezoid rule's own error, estimated by comparing it
  // with the rule over every other frame (Richardson: a third of their difference),
  // relative to the energy scale, the largest over the run (negative = not estimated). The
  // trust limit of the balance allows for it (run_trust.h).
  double energy_quadrature_error_max = -1.0;
  // How the work W of drives and damping in the energy balance E(t) - E(0) - W(t) was
  // computed: kEnergyWork* below ("" when there is no energy balance).
  std::string energy_work;

  // Constraint drift of the body formulations: the largest violation over the output frames
  // (negative = not applicable: the formulation has no constraints).
  double drift_position_max = -1.0;         // m, joint points apart (position level)
  double drift_orientation_max = -1.0;      // rad (small angles), joint axes / drive angles
  double drift_velocity_max = -1.0;         // m/s or rad/s, velocity-level constraints
  double quaternion_norm_error_max = -1.0;  // max | |e| - 1 | of the orientation quaternions

  LoopStats loops;
  ContactStats contact;
  RunSummary summary;  // over every frame computed, kept or not (the engine fills it)
  Trust trust = Trust::kNotAssessed;
  std::string trust_reason;           // kLow: which indicator, its value and its limit
  std::vector<std::string> warnings;  // the inputs' sanity warnings (input_sanity.h)
  double max_cpu_s = 0.0;             // s, the run's CPU budget (resolved)
  long max_steps = 0;                 // the run's step budget (resolved)

  // A run with an accuracy target (RunConfig::target): whether the verification found it met
  // (empty: not verified), and the choice with its reasoning and the check, as a JSON object
  // (server/choose/choice_json.h; "" when the run had no target).
  std::optional<bool> target_met;
  std::string choice_json;
};

// Frame-major arrays; frame k has time t[k], joints q[k*n .. k*n+n-1], and so on. With free
// bodies (model.h) q has positions() = num_positions values per frame (a free joint's 7), qd and
// tau num_dofs (its 6).
struct RunResult {
  int num_dofs = 0;       // velocity coordinates (nv), with closed loops the cut joints' too
  int num_positions = 0;  // position coordinates per frame when not num_dofs (0: num_dofs)
  int positions() const { return num_positions > 0 ? num_positions : num_dofs; }
  // One per velocity coordinate (num_dofs; coordinate_names.h: a free joint's NAME.vx ...).
  std::vector<std::string> joint_names;
  // When num_positions > 0: one name per position coordinate (NAME.x ... NAME.qz), and per
  // velocity coordinate the index of its joint's position in q (-1 for a free joint's). Else
  // empty.
  std::vector<std::string> position_names;
  std::vector<int> position_index;
  bool has_torques = false;
  bool has_energy = false;
  std::vector<double> t;                   // s
  std::vector<double> q, qd;               // rad, rad/s (or m, m/s)
  std::vector<double> tcp;                 // m, world frame, 3 per frame
  std::vector<double> tau;                 // drive efforts, N*m or N (when has_torques)
  std::vector<double> kinetic, potential;  // J (when has_energy)
  // A mechanism with closed loops run with RunConfig::want_loop_forces: the cut joints'
  // reactions, 6 per cut joint and frame in loop_force_names' order: the force (N) then the
  // torque (N*m, about the joint's origin) that the joint's parent side exerts on its child
  // side, in the world frame (LoopConstraints::Reactions). Empty otherwise.
  std::vector<std::string> loop_force_names;  // the cut joints
  std::vector<double> loop_forces;
  // J, the work of drives and damping since t = 0 at each frame, when the run integrates it
  // (RunStats::energy_work is kEnergyWorkIntegrated); empty otherwise.
  std::vector<double> work;
  // The contacts at the output frames and their summary (contact_log.h; inactive without).
  ContactLog contacts;
  // Seq of frame 0: the frames dropped before it. Nonzero only when the FrameSink keeps the
  // frames itself (FrameSink::KeepsFrames) and the arrays hold just the latest frame.
  long first_seq = 0;
  RunStats stats;
  // A finished joint-space run made with PilotLink::keep_integration: its integration, at
  // the last frame (run_prefix.h); null otherwise.
  std::shared_ptr<JointIntegration> integration;

  int num_frames() const { return static_cast<int>(t.size()); }
};

// Receives each frame as soon as it is computed (the server streams them).
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void OnFrame(const RunResult& result, int frame) = 0;
  // True when the sink keeps every frame itself (the server stores them as they come): the
  // RunResult then holds only the latest frame (index 0, seq first_seq), so a run's memory
  // does not grow with its length.
  virtual bool KeepsFrames() const { return false; }
};

}  // namespace mbstream
