#include "server/sim/joint_integration.h"

#include <cmath>

#include "server/sim/initial_state.h"

namespace mbstream {

std::unique_ptr<ContactForces> MakeContactForces(const Model& model,
                                                 const ContactSettings& settings) {
  if (!MayTouch(model, settings)) return nullptr;
  auto contact = std::make_unique<ContactForces>(model, settings);
  if (!contact->active()) return nullptr;
  return contact;
}

void CapContactStep(const Model& model, const ContactSettings& settings,
                    IntegratorOptions* options) {
  const double cap = ContactPeriod(model, settings) / kContactStepsPerPeriod;
  if (std::isfinite(cap) && (options->max_step <= 0.0 || cap < options->max_step)) {
    options->max_step = cap;
  }
}

JointIntegration::JointIntegration(const Model& model_in, const RunConfig& config,
                                   bool track_work_in, const IntegratorOptions& options)
    : model(model_in),
      drives(model, config.drives),
      contact(MakeContactForces(model, config.contact)),
      ode(model, drives, track_work_in, contact.get()),
      track_work(track_work_in),
      y(InitialJointState(config, drives, model)),
      integrator(MakeIntegrator(ode, 0.0, y.data(), options)) {}

SolverStats StatsSince(const SolverStats& now, const SolverStats& before) {
  SolverStats s = now;
  s.steps -= before.steps;
  s.rhs_evals -= before.rhs_evals;
  s.jac_evals -= before.jac_evals;
  s.nonlinear_iterations -= before.nonlinear_iterations;
  s.error_test_failures -= before.error_test_failures;
  s.convergence_failures -= before.convergence_failures;
  s.roots_found -= before.roots_found;
  return s;
}

}  // namespace mbstream
