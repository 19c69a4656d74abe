#include "server/sim/joint_run.h"

#include <array>
#include <cmath>
#include <memory>
#include <string>

#include "server/integrate/stiffness_estimate.h"
#include "server/sim/advance_to_frame.h"
#include "server/sim/frame_loop.h"
#include "server/sim/integrator_options_from.h"
#include "server/sim/joint_integration.h"
#include "server/sim/joint_space_ode.h"
#include "server/sim/run_contact.h"
#include "server/sim/run_prefix.h"
#include "server/sim/sampled_joint_run.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

// The integration's state as the frame loop drives it. Frames 0 .. prefix_frames - 1 are
// a prefix's (run_prefix.h), whose integration this run has taken over: their states and
// work are the prefix's, and the integrator goes on from the last of them.
class JointSpaceSource : public FrameSource {
 public:
  JointSpaceSource(JointIntegration& live, bool need_effort, BudgetTracking* budget,
                   const RunPrefix* prefix, size_t prefix_frames, ContactLog* contacts)
      : ode_(live.ode),
        integrator_(*live.integrator),
        y_(live.y),
        need_effort_(need_effort),
        budget_(budget),
        prefix_(prefix),
        prefix_frames_(prefix_frames),
        contacts_(contacts) {}

  bool Advance(const std::vector<double>& times, size_t k, RunStats* stats) override {
    frame_ = k;
    if (k < prefix_frames_) {
      LoadPrefixState(k);
      return true;
    }
    if (AdvanceToFrame(integrator_, times, k, y_.data(), stats, "", &budget_->t_stop)) return true;
    if (ode_.contact() != nullptr) stats->message += DeepestContactNote(*ode_.contact());
    if (stats->status == RunStatus::kTooMuchWork) {
      // The failure path only (it allocates); y is the last good state.
      budget_->eigenvalue = LargestEigenvalueEstimate(ode_, budget_->t_stop, y_.data());
    }
    return false;
  }

  bool Record(double t, FrameRecorder& recorder) override {
    if (ode_.num_quadratures() > 0) {
      if (frame_ < prefix_frames_) {
        recorder.SetWork(prefix_->work[frame_]);
      } else if (integrator_.Quadratures(work_.data())) {
        recorder.SetWork(work_[0]);
        if (ode_.num_quadratures() > 1 && contacts_ != nullptr) {
          contacts_->dissipated_work = work_[1];
        }
      }
    }
    const bool finite = ode_.EvaluateOutputs(t, y_.data(), need_effort_);
    if (finite && contacts_ != nullptr && ode_.contact() != nullptr) {
      contacts_->Record(t, *ode_.contact());
    }
    return finite &&
           recorder.Record(t, ode_.q(), ode_.qd(), need_effort_ ? &ode_.drive_effort() : nullptr);
  }

  std::string NonFiniteMessage(double t) const override {
    return "the state became non-finite at t = " + std::to_string(t) +
           " s; use a smaller step or an implicit method (bdf, dirk)" +
           (ode_.contact() != nullptr ? DeepestContactNote(*ode_.contact()) : std::string());
  }

 private:
  // y = [q; qd] of the prefix's frame k (allocates nothing).
  void LoadPrefixState(size_t k) {
    const size_t n = static_cast<size_t>(prefix_->num_dofs);
    for (size_t i = 0; i < n; ++i) {
      y_(static_cast<Eigen::Index>(i)) = prefix_->q[k * n + i];
      y_(static_cast<Eigen::Index>(n + i)) = prefix_->qd[k * n + i];
    }
  }

  JointSpaceOde& ode_;
  Integrator& integrator_;
  Eigen::VectorXd& y_;
  const bool need_effort_;
  BudgetTracking* budget_;
  const RunPrefix* prefix_;     // null without one
  const size_t prefix_frames_;  // frames taken from the prefix (0: none)
  ContactLog* contacts_;        // null: the frames' contacts are not kept
  size_t frame_ = 0;            // the frame being advanced to and recorded
  // J since t = 0 (when tracked): the integrated work of drives, damping and contacts; the
  // contacts' dissipated work (with contact).
  std::array<double, 2> work_{};
};

// `prefix`'s integration, taken over and retuned to `options`, when the prefix's frames
// are all on the run's first output times (at least two: the first is the initial state) and
// its integration, still there, is of this ODE; null otherwise (the run starts at t = 0; an
// integration that does not fit stays with the prefix for another run).
std::shared_ptr<JointIntegration> TakeOverPrefix(const RunPrefix* prefix,
                                                 const std::vector<double>& times, int n,
                                                 bool track_work, const IntegratorOptions& options,
                                                 size_t* prefix_frames) {
  *prefix_frames = 0;
  if (prefix == nullptr || prefix->num_dofs != n || prefix->frames() < 2 ||
      MatchingFrames(*prefix, times) != prefix->frames() ||
      prefix->q.size() != prefix->frames() * static_cast<size_t>(n) ||
      prefix->qd.size() != prefix->q.size() ||
      (track_work && prefix->work.size() != prefix->frames())) {
    return nullptr;
  }
  std::shared_ptr<JointIntegration> live =
      prefix->TakeIntegrationIf([&](JointIntegration& integration) {
        return integration.track_work == track_work && integration.ode.size() == 2 * n &&
               static_cast<int>(integration.drives.size()) == n &&
               integration.integrator->Retune(options);  // changes nothing when it refuses
      });
  if (live == nullptr) return nullptr;
  live->before = live->integrator->stats();
  *prefix_frames = prefix->frames();
  return live;
}

}  // namespace

void RunJointSpace(const Model& model, const RunConfig& config, const PilotLink& pilot,
                   const DriveSet& drives, const std::vector<double>& times,
                   FrameRecorder& recorder, RunResult& result, FrameSink* sink,
                   const std::atomic<bool>* cancel, BudgetTracking* budget, ControlLaw* control) {
  if (drives.any_sampled()) {
    RunSampledJointSpace(model, config, drives, times, recorder, result, sink, cancel, budget,
                         control);
    return;
  }
  const int n = model.num_dofs();
  // The work of drives and damping as a state of the ODE whenever there is any: a trapezoid
  // rule over the output frames would measure the output interval, not the integrator. The
  // appended state takes no part in the error control, so q and qd are those of the ODE
  // alone, bit for bit (appended_quadratures.h).
  const bool track_work =
      result.has_energy && (drives.any_work() || MayTouch(model, config.contact));
  IntegratorOptions options = IntegratorOptionsFrom(config, times.back(), budget->cpu_deadline_s);
  if (MayTouch(model, config.contact)) CapContactStep(model, config.contact, &options);
  size_t prefix_frames = 0;
  std::shared_ptr<JointIntegration> live =
      TakeOverPrefix(pilot.prefix.get(), times, n, track_work, options, &prefix_frames);
  if (live == nullptr)
    live = std::make_shared<JointIntegration>(model, config, track_work, options);
  if (track_work) recorder.UseIntegratedWork();
  result.stats.equations = live->ode.size();
  result.stats.jacobian_nnz = live->ode.JacobianNonZeros();
  result.stats.integrator = live->integrator->name();
  result.stats.continued_from_s = prefix_frames > 0 ? times[prefix_frames - 1] : 0.0;
  // Why contact is on or off (docs/contact.md), after the formulation's reason.
  AddContactReason(model, config.contact, live->contact.get(), options.max_step, &result.stats);
  StartContactLog(live->contact.get(), sink, &result.contacts);
  JointSpaceSource source(*live, result.has_torques || result.has_energy, budget,
                          pilot.prefix.get(), prefix_frames,
                          live->contact != nullptr ? &result.contacts : nullptr);
  RunFrames(times, source, recorder, result, sink, cancel);
  FinishContactLog(result.contacts, &result.stats);
  result.stats.solver = StatsSince(live->integrator->stats(), live->before);
  if (pilot.keep_integration && result.stats.status == RunStatus::kFinished) {
    result.integration = std::move(live);
  }
}

}  // namespace mbstream
