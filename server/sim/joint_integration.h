// A joint-space integration that can outlive its run: the model (with the run's gravity), the
// drives, the ODE, its state and the integrator. A run made with PilotLink::keep_integration
// hands it on (RunResult::integration); a later run of the same scene that continues those
// frames (PilotLink::prefix, run_prefix.h) takes it over and goes on from where it stopped,
// with its own tolerances, keeping the integrator's step size and order.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "server/drives/drive_set.h"
#include "server/integrate/integrator.h"
#include "server/model/model.h"
#include "server/sim/joint_space_ode.h"
#include "server/sim/run_config.h"

namespace mbstream {

struct JointIntegration {
  // At t = 0 from the run's initial state; `model` already has the run's gravity.
  JointIntegration(const Model& model, const RunConfig& config, bool track_work,
                   const IntegratorOptions& options);
  JointIntegration(const JointIntegration&) = delete;
  JointIntegration& operator=(const JointIntegration&) = delete;

  const Model model;
  const DriveSet drives;
  // The run's contact forces, or null when nothing may touch (contact_forces.h).
  const std::unique_ptr<ContactForces> contact;
  JointSpaceOde ode;
  const bool track_work;
  Eigen::VectorXd y;  // [q; qd] at the last output
  std::unique_ptr<Integrator> integrator;
  SolverStats before;  // the integrator's statistics when the current run took it over
};

// Whether a run of `model` under `settings` may have contact forces: contact on and two or more
// collision geometries (the pairs allowed decide: MakeContactForces).
inline bool MayTouch(const Model& model, const ContactSettings& settings) {
  return settings.enabled && model.collisions.size() >= 2;
}

// The contact forces of a run, or null when no pair may touch.
std::unique_ptr<ContactForces> MakeContactForces(const Model& model,
                                                 const ContactSettings& settings);

// Caps an adaptive method's step (options->max_step) at ContactPeriod / kContactStepsPerPeriod,
// so that no step jumps from free flight deep into a surface: for a run whose contact may act
// (the tree's and the closed loops' joint-space runs).
void CapContactStep(const Model& model, const ContactSettings& settings,
                    IntegratorOptions* options);

// `now` less `before` (the counts; the last step and order of `now`).
SolverStats StatsSince(const SolverStats& now, const SolverStats& before);

}  // namespace mbstream
