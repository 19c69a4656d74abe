#include "server/sim/sampled_joint_run.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>

#include "server/integrate/stiffness_estimate.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/sim/frame_loop.h"
#include "server/sim/initial_state.h"
#include "server/sim/integrator_options_from.h"
#include "server/sim/joint_integration.h"
#include "server/sim/joint_space_ode.h"
#include "server/sim/run_stop.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

void AddStats(const SolverStats& more, SolverStats* total) {
  total->steps += more.steps;
  total->rhs_evals += more.rhs_evals;
  total->jac_evals += more.jac_evals;
  total->nonlinear_iterations += more.nonlinear_iterations;
  total->error_test_failures += more.error_test_failures;
  total->convergence_failures += more.convergence_failures;
  total->roots_found += more.roots_found;
  total->last_step = more.last_step;
  total->last_order = more.last_order;
}

class SampledJointSource : public FrameSource {
 public:
  SampledJointSource(const Model& model, const RunConfig& config, const DriveSet& drives,
                     bool track_work, bool need_effort, const IntegratorOptions& options,
                     BudgetTracking* budget, ControlLaw* control)
      : model_(model),
        drives_(drives),
        contact_(MakeContactForces(model, config.contact)),
        ode_(model, drives, track_work, contact_.get()),
        y_(InitialJointState(config, drives, model)),
        q_(y_.head(model.nq())),
        qd_(y_.tail(model.nv())),
        options_(options),
        period_(drives.control_period()),
        epsilon_(1e-9 * drives.control_period()),
        duration_(config.duration),
        need_effort_(need_effort),
        budget_(budget),
        control_(control),
        kinematics_(model),
        commands_(drives.external_joints().size(), 0.0),
        sensors_(config.sensor_points.size(), Vector3d::Zero()) {
    for (const SensorPointConfig& sensor : config.sensor_points) {
      const int frame = model.FindFrame(sensor.link);
      MBSTREAM_CHECK_MSG(frame >= 0, "sensor point on an unknown link: ValidateRun refuses it");
      const Frame& f = model.frames[static_cast<size_t>(frame)];
      sensor_points_.push_back({f.body, f.X_BF.R * sensor.offset + f.X_BF.p});
    }
  }

  // The run's contact forces (null: nothing may touch) and its log of them (Start'ed here).
  const ContactForces* contact() const { return contact_.get(); }
  void KeepContacts(ContactLog* log) { contacts_ = log; }

  bool Advance(const std::vector<double>& times, size_t k, RunStats* stats) override {
    const double target = times[k];
    for (;;) {
      double at = static_cast<double>(step_) * period_;
      if (at > target + epsilon_ || at >= duration_ - epsilon_) break;
      if (at >= target - epsilon_) at = target;  // an instant on a frame: the frame's time
      if (at > t_ && !AdvanceTo(at, stats)) return false;
      if (!ControlInstant(at, stats)) return false;
      ++step_;
    }
    if (target > t_ && !AdvanceTo(target, stats)) return false;
    if (k + 1 == times.size() && control_ != nullptr) control_->Final(State(target));
    return true;
  }

  bool Record(double t, FrameRecorder& recorder) override {
    if (ode_.num_quadratures() > 0) {
      std::array<double, 2> work{};
      if (integrator_ != nullptr && integrator_->Quadratures(work.data())) {
        for (size_t k = 0; k < work.size(); ++k) work_[k] = work_base_[k] + work[k];
      }
      recorder.SetWork(work_[0]);
      if (ode_.num_quadratures() > 1 && contacts_ != nullptr) {
        contacts_->dissipated_work = work_[1];
      }
    }
    const bool finite = ode_.EvaluateOutputs(t, y_.data(), need_effort_);
    if (finite && contacts_ != nullptr && contact_ != nullptr) contacts_->Record(t, *contact_);
    return finite &&
           recorder.Record(t, ode_.q(), ode_.qd(), need_effort_ ? &ode_.drive_effort() : nullptr);
  }

  std::string NonFiniteMessage(double t) const override {
    return "the state became non-finite at t = " + std::to_string(t) +
           " s; use a smaller step or an implicit method (bdf, dirk), or check the commands";
  }

  SolverStats stats() const {
    SolverStats total = done_;
    if (integrator_ != nullptr) AddStats(integrator_->stats(), &total);
    return total;
  }
  const char* integrator_name() const { return integrator_ != nullptr ? integrator_->name() : ""; }
  const JointSpaceOde& ode() const { return ode_; }

 private:
  bool AdvanceTo(double t, RunStats* stats) {
    const AdvanceResult advance = integrator_->AdvanceTo(t, y_.data());
    if (advance.status != IntegratorStatus::kOk) {
      StopRun(stats, ToRunStatus(advance.status), advance.message);
      budget_->t_stop = advance.t;
      if (stats->status == RunStatus::kTooMuchWork) {  // the failure path only (it allocates)
        budget_->eigenvalue = LargestEigenvalueEstimate(ode_, advance.t, y_.data());
      }
      return false;
    }
    t_ = t;
    return true;
  }

  ControlState State(double t) {
    q_ = y_.head(model_.nq());
    qd_ = y_.tail(model_.nv());
    ControlState state;
    state.step = step_;
    state.t = t;
    state.q = &q_;
    state.qd = &qd_;
    state.model = &model_;
    if (model_.tcp_frame >= 0 || !sensor_points_.empty()) BodyKinematics(model_, kinematics_, q_);
    if (model_.tcp_frame >= 0) {
      state.tcp = FramePositionFromBodies(model_, kinematics_, model_.tcp_frame);
    }
    for (size_t i = 0; i < sensor_points_.size(); ++i) {
      const SensorPoint& point = sensor_points_[i];
      if (point.body == kBase) {
        sensors_[i] = point.in_body;
      } else {
        const Pose& X_WB = kinematics_.X_world[static_cast<size_t>(point.body)];
        sensors_[i] = X_WB.R * point.in_body + X_WB.p;
      }
    }
    state.sensors = &sensors_;
    // The contacts at (t, y): the contact law at the state (its forces as the next period's
    // first evaluation finds them).
    if (contact_ != nullptr && ode_.EvaluateOutputs(t, y_.data(), false)) {
      state.contacts = &contact_->contacts();
    }
    return state;
  }

  // Control instant t: the sampled servos' laws and the controller's commands held from now
  // on, the integrator started afresh at (t, y) up to the next instant: made at the first,
  // restarted in its own memory at the others (Integrator::Restart: no allocation).
  bool ControlInstant(double t, RunStats* stats) {
    if (integrator_ != nullptr) {
      std::array<double, 2> work{};
      if (integrator_->Quadratures(work.data())) {
        for (size_t k = 0; k < work.size(); ++k) work_base_[k] += work[k];
      }
      AddStats(integrator_->stats(), &done_);
    }
    // With free bodies or ball joints the state at an instant comes from the integrator's
    // interpolant, between projected steps: its quaternions are normalised before the
    // servos and the controller see it and the next period starts from it.
    if (model_.has_quaternions()) ode_.ProjectInPlace(t, y_.data());
    DriveSet::Workspace& held = ode_.drive_workspace();
    drives_.SampleServos(t, ode_.DrivePositions(y_.data()), y_.data() + model_.nq(), held);
    const std::vector<int>& external = drives_.external_joints();
    if (!external.empty()) {
      if (control_ == nullptr) {
        StopRun(stats, RunStatus::kFailed,
                "the run has external drives and no controller: run it on a server and "
                "command it over a Control stream");
        return false;
      }
      if (!control_->Command(State(t), commands_.data(), stats)) return false;
      for (size_t j = 0; j < external.size(); ++j) held.held[external[j]] = commands_[j];
    }
    period_options_ = options_;  // assigned, not made: no allocation for the table's name
    const double next = static_cast<double>(step_ + 1) * period_ + epsilon_;
    period_options_.t_final = std::min(options_.t_final, next);
    period_options_.max_steps = std::max(1L, options_.max_steps - done_.steps);
    if (integrator_ == nullptr || !integrator_->Restart(t, y_.data(), period_options_)) {
      integrator_ = MakeIntegrator(ode_, t, y_.data(), period_options_);
    }
    return true;
  }

  // A sensor point: its body (kBase: the base) and its position in the body's frame, m.
  struct SensorPoint {
    int body;
    Vector3d in_body;
  };

  const Model& model_;
  const DriveSet& drives_;
  const std::unique_ptr<ContactForces> contact_;  // null: nothing may touch
  JointSpaceOde ode_;
  Eigen::VectorXd y_;       // [q; qd] at t_
  Eigen::VectorXd q_, qd_;  // the controller's view of y_
  const IntegratorOptions options_;
  IntegratorOptions period_options_;  // the current period's (options_ up to its instant)
  const double period_;               // s, h
  const double epsilon_;              // s, an instant this near a frame is at the frame
  const double duration_;             // s
  const bool need_effort_;
  BudgetTracking* budget_;
  ControlLaw* control_;  // null: no controller
  Data kinematics_;      // the TCP at control instants
  std::vector<double> commands_;
  std::vector<SensorPoint> sensor_points_;  // RunConfig::sensor_points, resolved
  std::vector<Vector3d> sensors_;           // their world positions at the last state, m
  ContactLog* contacts_ = nullptr;          // the frames' contacts (null: not kept)
  std::unique_ptr<Integrator> integrator_;  // the current period's
  SolverStats done_;                        // the statistics of the periods before the current one
  double t_ = 0.0;                          // s, the time of y_
  long step_ = 0;                           // the next control instant's k
  // J: the work and the contacts' dissipated work (JointSpaceOde's quadratures) up to the
  // current period's start, and at the last frame.
  std::array<double, 2> work_base_{}, work_{};
};

}  // namespace

void RunSampledJointSpace(const Model& model, const RunConfig& config, const DriveSet& drives,
                          const std::vector<double>& times, FrameRecorder& recorder,
                          RunResult& result, FrameSink* sink, const std::atomic<bool>* cancel,
                          BudgetTracking* budget, ControlLaw* control) {
  const bool may_touch = MayTouch(model, config.contact);
  const bool track_work = result.has_energy && (drives.any_work() || may_touch);
  IntegratorOptions options = IntegratorOptionsFrom(config, times.back(), budget->cpu_deadline_s);
  if (may_touch) {  // no step from free flight deep into a surface (as RunJointSpace)
    const double cap = ContactPeriod(model, config.contact) / kContactStepsPerPeriod;
    if (std::isfinite(cap) && (options.max_step <= 0.0 || cap < options.max_step)) {
      options.max_step = cap;
    }
  }
  if (track_work) recorder.UseIntegratedWork();
  SampledJointSource source(model, config, drives, track_work,
                            result.has_torques || result.has_energy, options, budget, control);
  if (source.contact() != nullptr) {
    result.contacts.Start(*source.contact());
    result.contacts.keep_records = sink == nullptr || !sink->KeepsFrames();
    source.KeepContacts(&result.contacts);
  }
  result.stats.equations = source.ode().size();
  result.stats.jacobian_nnz = source.ode().JacobianNonZeros();
  RunFrames(times, source, recorder, result, sink, cancel);
  if (result.contacts.active) {  // as RunJointSpace
    result.stats.contact = result.contacts.Stats();
  }
  if (const std::string deep = result.contacts.DeepContactWarning(); !deep.empty()) {
    result.stats.warnings.push_back(deep);
  }
  result.stats.integrator = source.integrator_name();
  result.stats.solver = source.stats();
}

}  // namespace mbstream
