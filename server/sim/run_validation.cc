#include "server/sim/run_validation.h"

#include <cmath>
#include <string>

#include "common/check.h"
#include "common/format.h"
#include "server/body/body_model.h"
#include "server/integrate/failure_messages.h"
#include "server/integrate/integrator.h"
#include "server/sim/body_run.h"
#include "server/sim/integrator_options_from.h"

namespace mbstream {

namespace {

// The RunConfig's own ranges (server/spec checks the spec's fields; this guards the other
// callers of ValidateRun).
void CheckShape(const Model& model, const RunConfig& config) {
  if (static_cast<int>(config.drives.size()) != model.num_dofs()) {
    throw InputError(
        FormatString("the run has %d drives for a model of %d joints; give one "
                     "drive per joint (or none: passive)",
                     static_cast<int>(config.drives.size()), model.num_dofs()));
  }
  if (!(config.duration > 0.0 && std::isfinite(config.duration))) {
    throw InputError(
        FormatString("duration_s = %g: must be finite and > 0, e.g. 20", config.duration));
  }
  if (!(config.output_interval > 0.0 && std::isfinite(config.output_interval))) {
    throw InputError(FormatString("output_interval_s = %g: must be finite and > 0, e.g. 0.05",
                                  config.output_interval));
  }
}

// The method against the formulation it integrates (ChooseFormulation checks the body-index
// formulations' need of ida and body-baumgarte's refusal of it).
void CheckMethodFor(const RunConfig& config, const FormulationChoice& choice) {
  const std::string chosen = std::string("formulation ") + FormulationName(choice.formulation) +
                             (config.formulation == Formulation::kAuto ? " (chosen by auto)" : "");
  if (choice.formulation == Formulation::kJoint && config.method == Method::kIda) {
    throw InputError("method ida solves differential-algebraic equations, and " + chosen +
                     " is an ODE: use an ODE method (bdf, adams, erk, dirk, rk4, euler), or "
                     "formulation body-index3 or body-index2 for ida");
  }
  if (choice.formulation == Formulation::kBodyBaumgarte && config.method == Method::kEuler) {
    throw InputError(
        "method euler (semi-implicit Euler) needs a second-order ODE in positions and "
        "velocities, and " +
        chosen +
        " is not one (quaternions and body velocities): use rk4 or an adaptive method (bdf, "
        "adams, erk, dirk), or formulation joint with euler");
  }
}

}  // namespace

void CheckValidatedShape(const Model& model, const RunConfig& config) {
  MBSTREAM_CHECK_MSG(static_cast<int>(config.drives.size()) == model.num_dofs(),
                     "one drive per joint: ValidateRun first");
  MBSTREAM_CHECK_MSG(config.duration > 0.0 && std::isfinite(config.duration),
                     "a positive finite duration: ValidateRun first");
  MBSTREAM_CHECK_MSG(config.output_interval > 0.0 && std::isfinite(config.output_interval),
                     "a positive finite output interval: ValidateRun first");
}

FormulationChoice ValidatedFormulation(const Model& model, const RunConfig& config,
                                       const DriveSet& drives) {
  CheckValidatedShape(model, config);
  return ChooseFormulation(config, drives);
}

FormulationChoice ValidateRun(const Model& model, const RunConfig& config) {
  CheckShape(model, config);
  return ValidateRun(model, config, DriveSet(model, config.drives));
}

FormulationChoice ValidateRun(const Model& model, const RunConfig& config, const DriveSet& drives) {
  CheckShape(model, config);
  const FormulationChoice choice = ChooseFormulation(config, drives);
  if (config.target.any() && IsBodyFormulation(choice.formulation)) {
    throw InputError(std::string("an accuracy target is met with formulation auto, kinematic or "
                                 "joint, not ") +
                     FormulationName(choice.formulation) +
                     ": leave formulation out (auto), or drop the target and give method and "
                     "tolerances");
  }
  if (config.target.any() && (config.method == Method::kRk4 || config.method == Method::kEuler) &&
      !config.method_auto) {
    throw InputError(std::string("an accuracy target chooses tolerances, and method ") +
                     MethodName(config.method) +
                     " has none (a fixed step): use method auto (or bdf, adams, erk, dirk)");
  }
  if (choice.formulation == Formulation::kKinematic) return choice;  // nothing integrated
  if (model.num_dofs() == 0) {
    throw InputError(std::string("formulation: ") + FormulationName(choice.formulation) +
                     " integrates the motion of moving joints, and the model has none (every "
                     "joint is fixed): there is nothing to integrate; leave formulation out "
                     "(auto) or give kinematic");
  }
  CheckMethodFor(config, choice);
  if (IsBodyFormulation(choice.formulation)) CheckBodyFormulationHandles(model);
  CheckIntegratorOptions(IntegratorOptionsFrom(config, config.duration));
  return choice;
}

}  // namespace mbstream
