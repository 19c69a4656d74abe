#include "server/sim/joint_run.h"

#include <memory>
#include <string>

#include "server/integrate/stiffness_estimate.h"
#include "server/sim/advance_to_frame.h"
#include "server/sim/frame_loop.h"
#include "server/sim/initial_state.h"
#include "server/sim/integrator_options_from.h"
#include "server/sim/joint_space_ode.h"

namespace mbstream {

namespace {

class JointSpaceSource : public FrameSource {
 public:
  JointSpaceSource(JointSpaceOde& ode, Integrator& integrator, Eigen::VectorXd& y, bool need_effort,
                   BudgetTracking* budget)
      : ode_(ode), integrator_(integrator), y_(y), need_effort_(need_effort), budget_(budget) {}

  bool Advance(const std::vector<double>& times, size_t k, RunStats* stats) override {
    if (AdvanceToFrame(integrator_, times, k, y_.data(), stats, "", &budget_->t_stop)) return true;
    if (stats->status == RunStatus::kTooMuchWork) {
      // The failure path only (it allocates); y is the last good state.
      budget_->eigenvalue = LargestEigenvalueEstimate(ode_, budget_->t_stop, y_.data());
    }
    return false;
  }

  bool Record(double t, FrameRecorder& recorder) override {
    if (ode_.num_quadratures() > 0 && integrator_.Quadratures(&work_)) recorder.SetWork(work_);
    const bool finite = ode_.EvaluateOutputs(t, y_.data(), need_effort_);
    return finite &&
           recorder.Record(t, ode_.q(), ode_.qd(), need_effort_ ? &ode_.drive_effort() : nullptr);
  }

  std::string NonFiniteMessage(double t) const override {
    return "the state became non-finite at t = " + std::to_string(t) +
           " s; use a smaller step or an implicit method (bdf, dirk)";
  }

 private:
  JointSpaceOde& ode_;
  Integrator& integrator_;
  Eigen::VectorXd& y_;
  const bool need_effort_;
  BudgetTracking* budget_;
  double work_ = 0.0;  // J, the integrated work of drives and damping (when tracked)
};

}  // namespace

void RunJointSpace(const Model& model, const RunConfig& config, const DriveSet& drives,
                   const std::vector<double>& times, FrameRecorder& recorder, RunResult& result,
                   FrameSink* sink, const std::atomic<bool>* cancel, BudgetTracking* budget) {
  const int n = model.num_dofs();
  // The work as a state of the ODE where the scene dissipates: with damping the trapezoid
  // rule over the frames would be most of the "energy error". Without damping the drives'
  // work keeps the trapezoid (RunStats::energy_work says which), so that those runs take
  // exactly the steps they always took (an appended state changes the error norm's length).
  bool damped = false;
  for (int i = 0; i < drives.size(); ++i) damped = damped || drives.damping(i) > 0.0;
  const bool track_work = result.has_energy && damped;
  JointSpaceOde ode(model, drives, track_work);
  if (track_work) recorder.UseIntegratedWork();
  result.stats.equations = ode.size();
  result.stats.jacobian_nnz = ode.JacobianNonZeros();
  Eigen::VectorXd y = InitialJointState(config, drives, n);
  std::unique_ptr<Integrator> integrator = MakeIntegrator(
      ode, 0.0, y.data(), IntegratorOptionsFrom(config, times.back(), budget->cpu_deadline_s));
  result.stats.integrator = integrator->name();
  JointSpaceSource source(ode, *integrator, y, result.has_torques || result.has_energy, budget);
  RunFrames(times, source, recorder, result, sink, cancel);
  result.stats.solver = integrator->stats();
}

}  // namespace mbstream
