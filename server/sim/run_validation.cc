#include "server/sim/run_validation.h"

#include <cmath>
#include <string>

#include "server/body/body_model.h"
#include "server/integrate/failure_messages.h"
#include "server/integrate/integrator.h"
#include "server/sim/body_run.h"
#include "server/sim/contact_validation.h"
#include "server/sim/integrator_options_from.h"
#include "server/sim/joint_integration.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

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

namespace {

std::string FreeJointLabel(const Body& body) {
  return "free joint '" + body.joint.name + "' (link '" + body.name + "')";
}

}  // namespace

void RefuseFreeBodies(const Model& model, const std::string& what) {
  if (!model.has_free_bodies()) return;
  const Body& body = model.bodies[model.free_bodies.front()];
  throw InputError(FreeJointLabel(body) +
                   (model.free_bodies.size() > 1
                        ? " and " + std::to_string(model.free_bodies.size() - 1) + " more"
                        : std::string()) +
                   ": " + what);
}

void CheckFreeBodies(const Model& model, const RunConfig& config) {
  if (!model.has_free_bodies()) return;
  if (IsBodyFormulation(config.formulation)) {
    RefuseFreeBodies(model, std::string("formulation ") + FormulationName(config.formulation) +
                                " does not simulate free bodies yet; use formulation joint "
                                "(or auto)");
  }
  if (config.target.any()) {
    RefuseFreeBodies(model,
                     "an accuracy target does not choose the method for free bodies yet; give "
                     "method and tolerances (e.g. bdf, rtol 1e-8)");
  }
  const int nq = model.nq(), nv = model.nv();
  if (config.q0.size() != 0 && config.q0.size() != nq) {
    throw InputError(FormatString(
        "initial_q has %d values and the model has %d position coordinates: give none or one "
        "per coordinate, a free joint's 7 as x y z qw qx qy qz (docs/free_bodies.md)",
        static_cast<int>(config.q0.size()), nq));
  }
  if (config.qd0.size() != 0 && config.qd0.size() != nv) {
    throw InputError(FormatString(
        "initial_qd has %d values and the model has %d velocity coordinates: give none or one "
        "per coordinate, a free joint's 6 as vx vy vz (world) wx wy wz (body frame)",
        static_cast<int>(config.qd0.size()), nv));
  }
  for (const int i : model.free_bodies) {
    const Body& body = model.bodies[i];
    for (int k = 0; k < kFreeNv; ++k) {
      if (config.drives[static_cast<size_t>(body.v_index + k)].kind !=
          DriveConfig::Kind::kPassive) {
        throw InputError(FreeJointLabel(body) + " has a drive on its coordinate " +
                         std::to_string(k + 1) +
                         ": a free joint has no actuator; leave its drives out (passive)");
      }
    }
    if (config.q0.size() == nq) {
      const double* quat = config.q0.data() + body.q_index + 3;
      const double norm =
          std::sqrt(quat[0] * quat[0] + quat[1] * quat[1] + quat[2] * quat[2] + quat[3] * quat[3]);
      if (!(std::abs(norm - 1.0) <= 1e-6)) {
        throw InputError(FormatString(
            "%s: initial_q's quaternion (qw qx qy qz) = (%g, %g, %g, %g) has norm %.9g; give a "
            "unit quaternion (norm 1 within 1e-6)",
            FreeJointLabel(body).c_str(), quat[0], quat[1], quat[2], quat[3], norm));
      }
    }
  }
}

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
  CheckFreeBodies(model, config);
  return ValidateRun(model, config, DriveSet(model, config.drives));
}

void CheckSampledDrives(const Model& model, const RunConfig& config, const DriveSet& drives,
                        const FormulationChoice& choice) {
  if (!drives.any_sampled()) return;
  const int joint = drives.sampled_joints().front();
  const std::string what =
      "joint '" + model.bodies[static_cast<size_t>(model.BodyOfVelocity(joint))].joint.name +
      "' has a sampled drive (" +
      (drives.kind(joint) == DriveConfig::Kind::kExternal ? "external" : "pd_servo with period_s") +
      ")";
  if (choice.formulation != Formulation::kJoint) {
    throw InputError(what + ", which formulation " + FormulationName(choice.formulation) +
                     " does not run: give formulation joint (or auto)");
  }
  if (config.target.any()) {
    throw InputError(what +
                     ", and an accuracy target does not choose methods for sampled "
                     "drives yet: drop the target and give method and tolerances");
  }
  if (model.has_free_bodies()) {
    RefuseFreeBodies(model, what + ": sampled drives do not run with free bodies yet");
  }
  if (MayTouch(model, config.contact)) {
    throw InputError(what +
                     ", and the model's collision geometries may touch: sampled drives "
                     "do not run with contact yet; give contact.enabled false");
  }
}

FormulationChoice ValidateRun(const Model& model, const RunConfig& config, const DriveSet& drives) {
  CheckShape(model, config);
  CheckFreeBodies(model, config);
  CheckContact(model, config);
  const FormulationChoice choice = ChooseFormulation(config, drives);
  CheckSampledDrives(model, config, drives, choice);
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
