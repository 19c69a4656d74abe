#include "server/sim/body_run.h"

#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <utility>

#include "server/body/body_baumgarte_ode.h"
#include "server/body/body_cuts.h"
#include "server/body/body_dae.h"
#include "server/body/body_model.h"
#include "server/body/body_readout.h"
#include "server/body/consistent_init.h"
#include "server/integrate/failure_messages.h"
#include "server/integrate/ida_integrator.h"
#include "server/integrate/integrator.h"
#include "server/integrate/stiffness_estimate.h"
#include "server/sim/advance_to_frame.h"
#include "server/sim/frame_loop.h"
#include "server/sim/initial_state.h"
#include "server/sim/integrator_options_from.h"
#include "server/sim/joint_integration.h"
#include "server/sim/run_contact.h"
#include "server/sim/run_stop.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

// What to try when a body formulation's integration fails.
std::string Advice(Formulation formulation) {
  switch (formulation) {
    case Formulation::kBodyIndex3:
      return "; body-index3 (position-level constraints, a DAE of index 3) is known to defeat "
             "IDA's error test and Newton iteration at tight tolerances: use formulation "
             "body-index2 (method ida) or body-baumgarte (method bdf), or the joint "
             "formulation, which has no constraints at all";
    case Formulation::kBodyIndex2:
      return "; try a looser rtol, formulation body-baumgarte (method bdf) or the joint "
             "formulation";
    default:
      return "; try method bdf, different baumgarte parameters (alpha^2 = 4 beta, about the "
             "motion's bandwidth) or the joint formulation";
  }
}

// The body coordinates' state, read out in joint terms at each frame.
class BodySource : public FrameSource {
 public:
  BodySource(BodyReadout& readout, Integrator& integrator, Eigen::VectorXd& y,
             BodyBaumgarteOde* ode, std::string advice, bool need_effort, BudgetTracking* budget,
             Eigen::VectorXd* reactions, const ContactForces* contact, ContactLog* contacts)
      : readout_(readout),
        integrator_(integrator),
        y_(y),
        ode_(ode),
        advice_(std::move(advice)),
        need_effort_(need_effort),
        budget_(budget),
        reactions_(reactions),
        contact_(contact),
        contacts_(contacts) {}

  bool Advance(const std::vector<double>& times, size_t k, RunStats* stats) override {
    if (AdvanceToFrame(integrator_, times, k, y_.data(), stats, advice_, &budget_->t_stop)) {
      return true;
    }
    if (contact_ != nullptr) stats->message += DeepestContactNote(*contact_);
    if (stats->status == RunStatus::kTooMuchWork) {
      budget_->advice = advice_;
      // The failure path only (it allocates); the state y is the last good one.
      if (ode_) budget_->eigenvalue = LargestEigenvalueEstimate(*ode_, budget_->t_stop, y_.data());
    }
    return false;
  }

  bool Record(double t, FrameRecorder& recorder) override {
    if (ode_ != nullptr && ode_->num_quadratures() > 0 && integrator_.Quadratures(work_.data())) {
      recorder.SetWork(work_[0]);
      if (ode_->num_quadratures() > 1 && contacts_ != nullptr)
        contacts_->dissipated_work = work_[1];
    }
    // The readout evaluates the contacts at y too (BodyReadout::UseContact).
    const bool finite = readout_.Read(t, y_.data(), need_effort_ || reactions_ != nullptr);
    if (finite && reactions_ != nullptr) readout_.CutReactions(*reactions_);
    if (finite && contacts_ != nullptr) contacts_->Record(t, *contact_);
    extras_.tcp = readout_.tcp();
    extras_.kinetic = readout_.kinetic();
    extras_.potential = readout_.potential();
    return finite && recorder.Record(t, readout_.q(), readout_.qd(),
                                     need_effort_ ? &readout_.effort() : nullptr, &extras_);
  }

  std::string NonFiniteMessage(double t) const override {
    return FormatString("the state became non-finite at t = %g s", t) + advice_ +
           (contact_ != nullptr ? DeepestContactNote(*contact_) : std::string());
  }

 private:
  BodyReadout& readout_;
  Integrator& integrator_;
  Eigen::VectorXd& y_;
  BodyBaumgarteOde* ode_;  // null for the DAE formulations
  const std::string advice_;
  const bool need_effort_;
  BudgetTracking* budget_;
  Eigen::VectorXd* reactions_;    // the cut joints' reactions (null: not reported)
  const ContactForces* contact_;  // null without contact
  ContactLog* contacts_;          // null without contact
  FrameExtras extras_;
  // J since t = 0 (body-baumgarte): the integrated work of drives, damping and contacts; the
  // contacts' dissipated work (with contact).
  std::array<double, 2> work_{};
};

}  // namespace

bool IsBodyFormulation(Formulation formulation) {
  return formulation == Formulation::kBodyIndex3 || formulation == Formulation::kBodyIndex2 ||
         formulation == Formulation::kBodyBaumgarte;
}

void RunBody(const Model& model, const RunConfig& config, Formulation formulation,
             const DriveSet& drives, const std::vector<double>& times, FrameRecorder& recorder,
             RunResult& result, FrameSink* sink, const std::atomic<bool>* cancel,
             BudgetTracking* budget, const BodyLoops* loops) {
  const int n = model.num_dofs();
  const Eigen::VectorXd joint_state = InitialJointState(config, drives, n);
  const Eigen::VectorXd q0 = loops ? loops->q0 : Eigen::VectorXd(joint_state.head(n));
  const Eigen::VectorXd qd0 = loops ? loops->qd0 : Eigen::VectorXd(joint_state.tail(n));
  BodyModel bm = MakeBodyModel(model, drives, q0);
  if (loops != nullptr) {
    AddCutJoints(loops->loops, &bm);
    SelectCutRows(model, drives, q0, &bm);
  }
  const bool baumgarte = formulation == Formulation::kBodyBaumgarte;
  // Contact (body-baumgarte: contact_validation.h): the forces on the bodies at every
  // evaluation (body_contact.h), the pairs' signed distances as root functions, adaptive steps
  // capped at a fraction of the contact period, as in the joint-space runs.
  const std::unique_ptr<ContactForces> contact =
      baumgarte ? MakeContactForces(model, config.contact) : nullptr;

  std::unique_ptr<BodyBaumgarteOde> ode;
  std::unique_ptr<BodyDae> dae;
  BodyInitialState init;
  bool consistent = false;
  // body-baumgarte integrates the work of drives and damping with its ODE (a quadrature that
  // leaves the motion bit for bit as it is); the DAE formulations take the trapezoid rule
  // over the output frames (IDA has no quadratures: RunStats::energy_work says which).
  const bool track_work =
      baumgarte && result.has_energy && (drives.any_work() || contact != nullptr);
  if (baumgarte) {
    ode =
        std::make_unique<BodyBaumgarteOde>(bm, drives, config.baumgarte, track_work, contact.get());
    consistent = ConsistentInitialState(model, bm, ode->mechanics(), times.front(), q0, qd0, &init);
    result.stats.equations = ode->size();
    result.stats.jacobian_nnz = ode->JacobianNonZeros();
  } else {
    const ConstraintLevel level = formulation == Formulation::kBodyIndex3
                                      ? ConstraintLevel::kPosition
                                      : ConstraintLevel::kVelocity;
    dae = std::make_unique<BodyDae>(bm, drives, level);
    consistent = ConsistentInitialState(model, bm, dae->mechanics(), times.front(), q0, qd0, &init);
    result.stats.equations = dae->size();
    result.stats.jacobian_nnz = dae->JacobianNonZeros();
  }
  if (!consistent) {
    StopRun(&result.stats, RunStatus::kFailed,
            "the body formulation's constraints are singular at the initial pose (redundant or "
            "degenerate joints): no consistent initial accelerations; use the joint formulation");
    return;
  }

  Eigen::VectorXd y = baumgarte ? Eigen::VectorXd(init.y.head(bm.ode_size())) : init.y;
  std::unique_ptr<Integrator> integrator;
  IntegratorOptions options = IntegratorOptionsFrom(config, times.back(), budget->cpu_deadline_s);
  if (contact != nullptr) CapContactStep(model, config.contact, &options);
  if (baumgarte) {
    integrator = MakeIntegrator(*ode, times.front(), y.data(), options);
  } else {
    IdaOptions ida;
    ida.base = options;
    // IDA's own first step is tiny at tight tolerances (its estimate weighs the large
    // accelerations against small absolute tolerances), and below about 1e-9 s the index-2
    // iteration matrix is too ill-conditioned for Newton: start at a small fraction of the
    // output interval instead (IDA shrinks it if the error test asks).
    ida.initial_step = 1e-3 * config.output_interval;
    if (config.max_step > 0.0) ida.initial_step = std::min(ida.initial_step, config.max_step);
    integrator = MakeIdaIntegrator(*dae, times.front(), y.data(), init.yp.data(), ida);
  }
  result.stats.integrator = integrator->name();
  if (track_work) recorder.UseIntegratedWork();

  AddContactReason(model, config.contact, contact.get(), options.max_step, &result.stats);
  StartContactLog(contact.get(), sink, &result.contacts);

  BodyReadout readout(bm, drives);
  readout.SetStart(q0);
  readout.UseContact(contact.get());
  BodySource source(readout, *integrator, y, ode.get(), Advice(formulation),
                    result.has_torques || result.has_energy, budget,
                    loops != nullptr ? loops->reactions : nullptr, contact.get(),
                    contact != nullptr ? &result.contacts : nullptr);
  RunFrames(times, source, recorder, result, sink, cancel);
  FinishContactLog(result.contacts, &result.stats);
  result.stats.solver = integrator->stats();
  const ConstraintDrift& drift = readout.drift();
  result.stats.drift_position_max = drift.position;
  result.stats.drift_orientation_max = drift.orientation;
  result.stats.drift_velocity_max = drift.velocity;
  result.stats.quaternion_norm_error_max = drift.quaternion_norm;
}

}  // namespace mbstream
