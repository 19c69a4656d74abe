#include "server/sim/loop_run.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "server/drives/drive_set.h"
#include "server/dynamics/rnea.h"
#include "server/integrate/ida_integrator.h"
#include "server/integrate/thread_cpu_clock.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/kinematics/loop_coordinates.h"
#include "server/model/coordinate_names.h"
#include "server/sim/advance_to_frame.h"
#include "server/sim/body_run.h"
#include "server/sim/closed_loop_dae.h"
#include "server/sim/closed_loop_ode.h"
#include "server/sim/contact_log.h"
#include "server/sim/contact_validation.h"
#include "server/sim/frame_loop.h"
#include "server/sim/frame_recorder.h"
#include "server/sim/input_sanity.h"
#include "server/sim/integrator_options_from.h"
#include "server/sim/joint_integration.h"
#include "server/sim/loop_plan.h"
#include "server/sim/run_budget.h"
#include "server/sim/run_contact.h"
#include "server/sim/run_stop.h"
#include "server/sim/run_trust.h"
#include "server/sim/run_validation.h"
#include "server/sim/simulate.h"
#include "server/sim/singular_pose.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

// The largest constraint residuals over the frames, into RunStats' drift figures.
void TrackResiduals(double gap, double alignment, double velocity, RunStats* stats) {
  stats->drift_position_max = std::max(stats->drift_position_max, gap);
  stats->drift_orientation_max = std::max(stats->drift_orientation_max, alignment);
  stats->drift_velocity_max = std::max(stats->drift_velocity_max, velocity);
}

// Every degree of freedom prescribed: the loops solved by Newton at each frame, from the
// previous frame's pose; velocities and accelerations from the linear constraints; the
// prescribed joints' efforts from inverse dynamics and the multipliers.
class KinematicLoopSource : public FrameSource {
 public:
  KinematicLoopSource(const Model& model, const std::vector<LoopClosure>& loops,
                      const DriveSet& drives, const LoopPlan& plan, bool want_torques,
                      Eigen::VectorXd* reactions, RunStats* stats)
      : model_(model),
        drives_(drives),
        want_torques_(want_torques),
        reactions_(reactions),
        stats_(stats),
        data_(model),
        constraints_(model, loops),
        prescribed_(PrescribedJoints(drives)),
        solver_(model, constraints_, prescribed_),
        q_(plan.q0),
        qd_(Eigen::VectorXd::Zero(model.num_dofs())),
        qdd_(Eigen::VectorXd::Zero(model.num_dofs())),
        held_q_(Eigen::VectorXd::Zero(model.num_dofs())),
        held_qd_(Eigen::VectorXd::Zero(model.num_dofs())),
        held_qdd_(Eigen::VectorXd::Zero(model.num_dofs())),
        force_(model.num_dofs()),
        effort_(Eigen::VectorXd::Zero(model.num_dofs())),
        last_q_(plan.q0) {
    bool independent = false;
    rows_ = solver_.Analyse(data_, q_, &independent).independent;
    mu_.resize(solver_.num_rows());
    singular_.emplace(model, solver_.num_rows());
  }

  bool Advance(const std::vector<double>& times, size_t k, RunStats* stats) override {
    const double t = times[k];
    for (int j : prescribed_) {
      const TrajectoryPoint ref = drives_.Reference(j, t);
      held_q_(j) = ref.q;
      held_qd_(j) = ref.qd;
      held_qdd_(j) = ref.qdd;
    }
    if (solver_.SolvePositions(data_, q_, held_q_, kLoopAssemblyTolerance, 50) < 0) {
      stats->status = RunStatus::kConvergenceFailures;
      stats->message = FormatString(
          "the loops cannot be closed at t = %.6g s (Newton: largest residual %.3g m or rad): "
          "the prescribed motion leaves the mechanism's reach or passes a singular pose; "
          "check the drives' ranges (the last pose closed, at t = %.6g s: %s)",
          t, solver_.residual().cwiseAbs().maxCoeff(), k > 0 ? times[k - 1] : 0.0,
          PoseText(model_, last_q_).c_str());
      return false;
    }
    solver_.SolveVelocities(data_, qd_, held_qd_);
    if (const auto singular = singular_->Check(t, q_, solver_.constraint_rows())) {
      StopRun(stats, RunStatus::kFailed, *singular);
      return false;
    }
    solver_.SolveAccelerations(data_, qd_, qdd_, held_qdd_);
    last_q_ = q_;
    return true;
  }

  bool Record(double t, FrameRecorder& recorder) override {
    const LoopConstraints& c = constraints_;
    TrackResiduals(c.MaxGap(solver_.residual()), c.MaxAlignment(solver_.residual()),
                   solver_.velocity_residual().cwiseAbs().maxCoeff(), stats_);
    if (want_torques_ || reactions_ != nullptr) {
      force_ = Rnea(model_, data_, q_, qd_, qdd_);
      for (int i = 0; i < model_.num_dofs(); ++i) force_(i) += drives_.damping(i) * qd_(i);
      solver_.Multipliers(force_, mu_);
      const Eigen::Index r = mu_.size() - static_cast<Eigen::Index>(prescribed_.size());
      for (size_t h = 0; h < prescribed_.size(); ++h) {
        effort_(prescribed_[h]) = mu_(r + static_cast<Eigen::Index>(h));
      }
      // mu's first entries are the independent loop rows' (LoopSolver::Multipliers).
      if (reactions_ != nullptr) constraints_.Reactions(data_, rows_, mu_, *reactions_);
    }
    return recorder.Record(t, q_, qd_, want_torques_ ? &effort_ : nullptr);
  }

  std::string NonFiniteMessage(double t) const override {
    return "a prescribed trajectory gave a non-finite value at t = " + std::to_string(t) +
           " s; check the drives' parameters";
  }

 private:
  const Model& model_;
  const DriveSet& drives_;
  const bool want_torques_;
  Eigen::VectorXd* reactions_;  // null: not asked for
  RunStats* stats_;
  Data data_;
  LoopConstraints constraints_;
  const std::vector<int> prescribed_;
  LoopSolver solver_;
  std::vector<int> rows_;  // the independent rows of the loop constraints
  Eigen::VectorXd q_, qd_, qdd_, held_q_, held_qd_, held_qdd_, force_, effort_, mu_;
  Eigen::VectorXd last_q_;                     // the last frame's pose, for messages
  std::optional<SingularPoseWatch> singular_;  // sized once the rows are known
};

// Stops a run whose constraint matrix A's RowConditioning fell to `conditioning` below
// kSingularPoseConditioning at time t and pose q, or whose integrator failed there.
void StopSingular(const Model& model, const Eigen::VectorXd& q, double t, double conditioning,
                  RunStats* stats) {
  StopRun(
      stats, RunStatus::kFailed,
      FormatString("the loop constraints became singular at t = %.6g s (smallest singular value of "
                   "the constraint Jacobian, rows scaled to unit length, %.2g of its largest): the "
                   "mechanism reached a singular configuration, where the loops no longer "
                   "determine its motion and its joint forces are unbounded (a Delta robot: its "
                   "rods all parallel; a dead centre); add joint limits or shorten the run (the "
                   "pose: %s)",
                   t, conditioning, PoseText(model, q).c_str()));
}

// The joint-space ODE with the loops as constraints, integrated frame to frame.
class ClosedLoopSource : public FrameSource {
 public:
  ClosedLoopSource(ClosedLoopOde& ode, Integrator& integrator, Eigen::VectorXd& y,
                   BudgetTracking* budget, Eigen::VectorXd* reactions, RunStats* stats,
                   ContactLog* contacts)
      : ode_(ode),
        integrator_(integrator),
        y_(y),
        budget_(budget),
        reactions_(reactions),
        stats_(stats),
        contacts_(contacts) {}

  bool Advance(const std::vector<double>& times, size_t k, RunStats* stats) override {
    if (!AdvanceToFrame(integrator_, times, k, y_.data(), stats, "", &budget_->t_stop)) {
      // y_ holds the state at t_stop: a failure at a singular pose is said to be one.
      const double t = budget_->t_stop;
      if (ode_.Evaluate(t, y_.data())) {
        const double conditioning = ode_.ConstraintConditioning();
        if (conditioning < kSingularPoseConditioning) {
          StopSingular(ode_.model(), ode_.q(), t, conditioning, stats);
        }
      }
      return false;
    }
    if (k == 0) return true;
    // At each frame: stop at (near) a singular pose rather than grind towards it.
    if (ode_.Evaluate(times[k], y_.data())) {
      const double conditioning = ode_.ConstraintConditioning();
      if (conditioning < kSingularPoseConditioning) {
        StopSingular(ode_.model(), ode_.q(), times[k], conditioning, stats);
        return false;
      }
    }
    return true;
  }

  bool Record(double t, FrameRecorder& recorder) override {
    if (ode_.model().has_quaternions()) {  // the integrator's own, before Evaluate normalises
      stats_->quaternion_norm_error_max =
          std::max(stats_->quaternion_norm_error_max, ode_.QuaternionNormError(y_.data()));
    }
    if (!ode_.Evaluate(t, y_.data())) return false;
    double gap = 0.0, alignment = 0.0, velocity = 0.0;
    ode_.Residuals(&gap, &alignment, &velocity);
    TrackResiduals(gap, alignment, velocity, stats_);
    if (reactions_ != nullptr) ode_.Reactions(reactions_);
    if (contacts_ != nullptr && ode_.contact() != nullptr) contacts_->Record(t, *ode_.contact());
    if (ode_.num_quadratures() > 0) {  // with contact: the work integrated with the ODE
      if (integrator_.Quadratures(work_.data())) {
        recorder.SetWork(work_[0]);
        if (contacts_ != nullptr) contacts_->dissipated_work = work_[1];
      }
    } else {  // the loops' power joins the drives' (a trapezoid over the frames)
      recorder.SetConstraintPower(ode_.ConstraintPower());
    }
    return recorder.Record(t, ode_.q(), ode_.qd(), &ode_.drive_effort());
  }

  std::string NonFiniteMessage(double t) const override {
    return FormatString(
        "the state became non-finite or the loop constraints singular at t = %.6g s; use a "
        "smaller step or tolerance, or check that the mechanism does not pass a singular pose",
        t);
  }

 private:
  ClosedLoopOde& ode_;
  Integrator& integrator_;
  Eigen::VectorXd& y_;
  BudgetTracking* budget_;
  Eigen::VectorXd* reactions_;  // null: not asked for
  RunStats* stats_;
  ContactLog* contacts_;          // null: no contact, or the frames' contacts are not kept
  std::array<double, 2> work_{};  // J since t = 0 (with contact): the work; the dissipated
};

// The index-2 GGL DAE, integrated frame to frame by IDA.
class ClosedLoopDaeSource : public FrameSource {
 public:
  ClosedLoopDaeSource(ClosedLoopDae& dae, Integrator& integrator, Eigen::VectorXd& y, int n,
                      BudgetTracking* budget, Eigen::VectorXd* reactions, RunStats* stats)
      : dae_(dae),
        integrator_(integrator),
        y_(y),
        budget_(budget),
        reactions_(reactions),
        stats_(stats),
        q_(n),
        qd_(n),
        effort_(n) {}

  // As the ODE's source: a frame at (near) a singular pose stops the run, and an integrator's
  // failure at one is put down to it.
  bool Advance(const std::vector<double>& times, size_t k, RunStats* stats) override {
    if (!AdvanceToFrame(integrator_, times, k, y_.data(), stats, "", &budget_->t_stop)) {
      StopIfSingular(budget_->t_stop, stats);  // y_ holds the state at t_stop
      return false;
    }
    return k == 0 || !StopIfSingular(times[k], stats);
  }

  bool Record(double t, FrameRecorder& recorder) override {
    const Eigen::Index n = q_.size();
    q_ = y_.head(n);
    qd_ = y_.segment(n, n);
    double gap = 0.0, alignment = 0.0, velocity = 0.0;
    dae_.Readout(t, y_.data(), &effort_, &gap, &alignment, &velocity);
    if (reactions_ != nullptr) dae_.Reactions(y_.data(), reactions_);
    TrackResiduals(gap, alignment, velocity, stats_);
    recorder.SetConstraintPower(dae_.ConstraintPower(y_.data()));
    return recorder.Record(t, q_, qd_, &effort_);
  }

  std::string NonFiniteMessage(double t) const override {
    return FormatString("the state became non-finite at t = %.6g s; use a smaller tolerance", t);
  }

 private:
  bool StopIfSingular(double t, RunStats* stats) {
    const double conditioning = dae_.ConstraintConditioning(y_.data());
    if (!(conditioning < kSingularPoseConditioning)) return false;
    q_ = y_.head(q_.size());
    StopSingular(dae_.model(), q_, t, conditioning, stats);
    return true;
  }

  ClosedLoopDae& dae_;
  Integrator& integrator_;
  Eigen::VectorXd& y_;
  BudgetTracking* budget_;
  Eigen::VectorXd* reactions_;  // null: not asked for
  RunStats* stats_;
  Eigen::VectorXd q_, qd_, effort_;
};

// Output times as SimulateTree takes them: k * interval, and the duration last.
std::vector<double> LoopOutputTimes(double duration, double interval) {
  std::vector<double> times;
  const long count = OutputFrameCount(duration, interval);
  times.reserve(static_cast<size_t>(count));
  for (long k = 0; k < count; ++k) times.push_back(std::min(duration, k * interval));
  times.back() = duration;
  return times;
}

RunConfig TreeConfigOf(const RunConfig& config) {
  RunConfig tree = config;  // the tree's checks, without the kinematic formulation's
  if (tree.formulation == Formulation::kKinematic) tree.formulation = Formulation::kJoint;
  // The GGL DAE's tolerances are the ODE's; the body DAEs take ida as for a tree.
  if (tree.method == Method::kIda && !IsBodyFormulation(tree.formulation)) {
    tree.method = Method::kBdf;
  }
  return tree;
}

// The result before any frame: every joint of the file (the tree's, then the cut joints'
// coordinates, computed from the tree's state: loop_coordinates.h), the formulation and how
// the loops close.
RunResult StartLoopResult(const Model& model, const std::vector<LoopClosure>& loops,
                          const RunConfig& config, const LoopPlan& plan,
                          const LoopCoordinates& cut_coordinates) {
  const bool kinematic = plan.choice.formulation == Formulation::kKinematic;
  RunResult result;
  result.num_dofs = model.num_dofs() + cut_coordinates.size();
  if (model.has_quaternions()) {  // as SimulateTree's, the cut joints' coordinates after
    result.joint_names = VelocityNames(model);
    result.num_positions = model.nq() + cut_coordinates.size();
    result.position_names = PositionNames(model);
    result.position_index.assign(static_cast<size_t>(result.num_dofs), -1);
    for (const Body& body : model.bodies) {
      if (body.nv() == 1) result.position_index[static_cast<size_t>(body.v_index)] = body.q_index;
    }
    for (int k = 0; k < cut_coordinates.size(); ++k) {
      result.position_index[static_cast<size_t>(model.nv() + k)] = model.nq() + k;
    }
  } else {
    for (const Body& body : model.bodies) result.joint_names.push_back(body.joint.name);
  }
  for (std::string& name : LoopCoordinateNames(loops)) {
    if (model.has_quaternions()) result.position_names.push_back(name);
    result.joint_names.push_back(name);
  }
  result.has_torques = config.want_torques;
  result.has_energy = !kinematic;
  RunStats& stats = result.stats;
  stats.formulation = FormulationName(plan.choice.formulation);
  stats.formulation_reason = plan.choice.reason;
  stats.method = kinematic ? "none" : MethodName(config.method);
  stats.integrator = kinematic ? "none (Newton on the loops at each frame)" : "";
  stats.warnings = WarningMessages(CheckInputSanity(model, config));
  stats.max_steps = config.max_steps;
  stats.max_cpu_s = config.max_cpu_s;
  stats.drift_position_max = stats.drift_orientation_max = stats.drift_velocity_max = 0.0;
  if (model.has_quaternions() && !kinematic) stats.quaternion_norm_error_max = 0.0;
  for (const LoopClosure& loop : loops) {
    stats.loops.cut_joints.push_back(loop.name + " (" + LoopJointTypeName(loop.type) + ")");
  }
  stats.loops.equations = plan.rank.equations;
  stats.loops.independent = plan.rank.rank;
  stats.loops.mobility = plan.rank.mobility;
  stats.loops.assembly = plan.assembly;
  return result;
}

// Everything a loop run's frame loop needs besides the formulation's source.
struct LoopFrames {
  const std::vector<double>& times;
  FrameRecorder& recorder;
  RunResult& result;
  FrameSink* sink;
  const std::atomic<bool>* cancel;
  BudgetTracking* budget;
  Eigen::VectorXd* reactions;  // the cut joints' reactions when asked for, else null
};

// Method ida: the index-2 GGL DAE (closed_loop_dae.h).
void RunLoopDae(const Model& model, const std::vector<LoopClosure>& loops, const RunConfig& config,
                const DriveSet& drives, const LoopPlan& plan, const LoopFrames& frames) {
  RunStats& stats = frames.result.stats;
  MBSTREAM_CHECK_MSG(!model.has_quaternions(), "ValidateLoopRun refuses ida with quaternions");
  ClosedLoopDae dae(model, loops, drives, plan.rank);
  Eigen::VectorXd y, yp;
  dae.ConsistentStart(0.0, plan.q0, plan.qd0, &y, &yp);
  IdaOptions ida;
  ida.base = IntegratorOptionsFrom(config, frames.times.back(), frames.budget->cpu_deadline_s);
  ida.linear_solver = IdaOptions::LinearSolver::kDense;
  ida.initial_step = 1e-3 * config.output_interval;
  if (config.max_step > 0.0) ida.initial_step = std::min(ida.initial_step, config.max_step);
  std::unique_ptr<Integrator> integrator = MakeIdaIntegrator(dae, 0.0, y.data(), yp.data(), ida);
  stats.equations = dae.size();
  stats.jacobian_nnz = dae.JacobianNonZeros();
  stats.integrator = std::string(integrator->name()) + " (index-2 GGL)";
  ClosedLoopDaeSource source(dae, *integrator, y, model.num_dofs(), frames.budget, frames.reactions,
                             &stats);
  RunFrames(frames.times, source, frames.recorder, frames.result, frames.sink, frames.cancel);
  stats.solver = integrator->stats();
}

// An ODE method: the Baumgarte ODE, projected after each step of BDF (closed_loop_ode.h).
void RunLoopOde(const Model& model, const std::vector<LoopClosure>& loops, const RunConfig& config,
                const DriveSet& drives, const LoopPlan& plan, const LoopFrames& frames) {
  RunStats& stats = frames.result.stats;
  // The projection's Newton tolerance: well below the run's atol, or CVODE takes the
  // leftover for a correction too large and shrinks the step. Below atol 1e-13 it is
  // under round-off and the projection fails (docs/closed_loops.md).
  // Contact as for a tree (joint_run.cc): the forces in the right-hand side, the pairs' signed
  // distances as root functions, adaptive steps capped at a fraction of the contact period.
  const std::unique_ptr<ContactForces> contact = MakeContactForces(model, config.contact);
  ClosedLoopOde ode(model, loops, drives, plan.q0, config.baumgarte,
                    std::min(1e-10, 0.01 * config.atol), contact.get());
  Eigen::VectorXd y(model.nq() + model.nv());
  y << plan.q0, plan.qd0;
  IntegratorOptions options =
      IntegratorOptionsFrom(config, frames.times.back(), frames.budget->cpu_deadline_s);
  if (contact != nullptr) CapContactStep(model, config.contact, &options);
  std::unique_ptr<Integrator> integrator = MakeIntegrator(ode, 0.0, y.data(), options);
  stats.equations = ode.size();
  stats.jacobian_nnz = ode.size() * ode.size();
  stats.integrator =
      std::string(integrator->name()) + (config.method == Method::kBdf ? " with projection" : "");
  ContactLog& log = frames.result.contacts;
  if (contact != nullptr) frames.recorder.UseIntegratedWork();
  AddContactReason(model, config.contact, contact.get(), options.max_step, &stats);
  StartContactLog(contact.get(), frames.sink, &log);
  ClosedLoopSource source(ode, *integrator, y, frames.budget, frames.reactions, &stats,
                          contact != nullptr ? &log : nullptr);
  RunFrames(frames.times, source, frames.recorder, frames.result, frames.sink, frames.cancel);
  FinishContactLog(log, &stats);
  stats.solver = integrator->stats();
}

// Free bodies and ball joints in the spanning tree run with formulation joint and an ODE
// method (closed_loop_ode.h: q on its manifold, the Jacobian in velocity space); method ida (the
// GGL DAE) and the body formulations keep one position per velocity, and are refused naming the
// joint and what to use instead.
void RefuseLoopQuaternions(const Model& model, const RunConfig& config) {
  if (!model.has_quaternions()) return;
  for (const Body& body : model.bodies) {  // a pose drive (pose_motion.h) on a free or ball joint
    if (body.nv() == 1) continue;
    for (int k = 0; k < body.nv(); ++k) {
      const size_t v = static_cast<size_t>(body.v_index + k);
      if (v < config.drives.size() && config.drives[v].kind != DriveConfig::Kind::kPassive) {
        throw InputError(std::string(body.free() ? "free" : "ball") + " joint '" + body.joint.name +
                         "' (link '" + body.name +
                         "') has a drive, and a mechanism with closed loops takes drives on "
                         "one-coordinate joints only (a prescribed pose is not a loop "
                         "constraint yet); leave it passive and prescribe a revolute or "
                         "prismatic joint of the loop, or open the loop");
      }
    }
  }
  std::string what;
  if (IsBodyFormulation(config.formulation)) {
    what = std::string("formulation ") + FormulationName(config.formulation) +
           " does not simulate it in a mechanism with closed loops; use formulation joint (or "
           "auto) with an ODE method (bdf projects onto the loops after each step)";
  } else if (config.method == Method::kIda) {
    what =
        "method ida (the closed loops' index-2 DAE) does not simulate it yet; use method bdf "
        "(the joint-space ODE projected onto the loops and the unit quaternions after each "
        "step), or adams, erk, dirk";
  } else {
    return;
  }
  if (model.has_free_bodies()) RefuseFreeBodies(model, what);
  RefuseBallJoints(model, what);
}

}  // namespace

FormulationChoice ValidateLoopRun(const Model& model, const std::vector<LoopClosure>& loops,
                                  const RunConfig& config) {
  if (loops.empty()) return ValidateRun(model, config);
  CheckContact(model, config, loops);
  RefuseLoopQuaternions(model, config);
  const DriveSet drives(model, config.drives);
  if (drives.any_sampled()) {
    throw InputError(
        "a mechanism with closed loops does not run sampled drives (external, pd_servo with "
        "period_s) yet; give continuous drives or open the loop");
  }
  const LoopPlan plan = PlanLoopRun(model, loops, config, drives);
  ValidateRun(model, TreeConfigOf(config), drives);
  return plan.choice;
}

RunResult SimulateLoops(const Model& model_in, const std::vector<LoopClosure>& loops,
                        const RunConfig& config_in, FrameSink* sink,
                        const std::atomic<bool>* cancel) {
  if (loops.empty()) return SimulateTree(model_in, config_in, sink, cancel);
  const double cpu0 = ThreadCpuSeconds();
  const auto wall0 = std::chrono::steady_clock::now();
  Model model = model_in;
  model.gravity = config_in.gravity;
  RunConfig config = config_in;
  ResolveBudget(model.num_dofs(), &config);
  const DriveSet drives(model, config.drives);  // CHECKs one per joint
  CheckValidatedShape(model, config);           // ValidateLoopRun at the door did the rest
  const LoopPlan plan = PlanLoopRun(model, loops, config, drives);

  LoopCoordinates cut_coordinates(model, loops);
  RunResult result = StartLoopResult(model, loops, config, plan, cut_coordinates);
  RunStats& stats = result.stats;
  const std::vector<double> times = LoopOutputTimes(config.duration, config.output_interval);
  FrameRecorder recorder(model, drives, result, times.size(), /*track_tcp_error=*/false,
                         /*latest_only=*/sink != nullptr && sink->KeepsFrames());
  recorder.AppendLoopCoordinates(&cut_coordinates);
  Eigen::VectorXd reactions = Eigen::VectorXd::Zero(6 * static_cast<Eigen::Index>(loops.size()));
  if (config.want_loop_forces) {  // PlanLoopRun refused it where it is not computed
    for (const LoopClosure& loop : loops) result.loop_force_names.push_back(loop.name);
    recorder.AppendLoopForces(&reactions);
  }
  BudgetTracking budget;
  budget.cpu_deadline_s = cpu0 + config.max_cpu_s;
  const LoopFrames frames{times,
                          recorder,
                          result,
                          sink,
                          cancel,
                          &budget,
                          config.want_loop_forces ? &reactions : nullptr};
  if (plan.choice.formulation == Formulation::kKinematic) {
    KinematicLoopSource source(model, loops, drives, plan, config.want_torques, frames.reactions,
                               &stats);
    RunFrames(times, source, recorder, result, sink, cancel);
  } else if (IsBodyFormulation(plan.choice.formulation)) {
    const BodyLoops body_loops{loops, plan.q0, plan.qd0, frames.reactions};
    RunBody(model, config, plan.choice.formulation, drives, times, recorder, result, sink, cancel,
            &budget, &body_loops);
  } else if (config.method == Method::kIda) {
    RunLoopDae(model, loops, config, drives, plan, frames);
  } else {
    RunLoopOde(model, loops, config, drives, plan, frames);
  }
  stats.cpu_s = ThreadCpuSeconds() - cpu0;
  stats.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  AssessTrust(&stats, TrustScaleOf(model, config, plan.choice.formulation));
  return result;
}

}  // namespace mbstream
