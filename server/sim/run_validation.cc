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

std::string BallJointLabel(const Body& body) {
  return "ball joint '" + body.joint.name + "' (link '" + body.name + "')";
}

std::string AndMore(size_t count) {
  return count > 1 ? " and " + std::to_string(count - 1) + " more" : std::string();
}

// initial_q and initial_qd of a model with quaternions: nq and nv values.
void CheckCoordinateCounts(const Model& model, const RunConfig& config) {
  const int nq = model.nq(), nv = model.nv();
  if (config.q0.size() != 0 && config.q0.size() != nq) {
    throw InputError(FormatString(
        "initial_q has %d values and the model has %d position coordinates: give none or one "
        "per coordinate, a free joint's 7 as x y z qw qx qy qz, a ball joint's 4 as qw qx qy qz "
        "(docs/free_bodies.md)",
        static_cast<int>(config.q0.size()), nq));
  }
  if (config.qd0.size() != 0 && config.qd0.size() != nv) {
    throw InputError(FormatString(
        "initial_qd has %d values and the model has %d velocity coordinates: give none or one "
        "per coordinate, a free joint's 6 as vx vy vz (world) wx wy wz (body frame), a ball "
        "joint's 3 as wx wy wz (child frame)",
        static_cast<int>(config.qd0.size()), nv));
  }
}

// The drives on a free or ball joint's coordinates: none (passive), or a prescribed pose
// (pose_motion.h: prescribed drives on some of them, the rest held) in a kinematic run.
void CheckPoseDrives(const Model& model, const Body& body, const RunConfig& config,
                     const std::string& label, const char* what) {
  bool posed = false;
  for (int k = 0; k < body.nv(); ++k) {
    const DriveConfig& drive = config.drives[static_cast<size_t>(body.v_index + k)];
    if (drive.kind == DriveConfig::Kind::kPassive) continue;
    if (drive.kind != DriveConfig::Kind::kPrescribed || drive.velocity_source) {
      throw InputError(label + " has a drive on its coordinate " + std::to_string(k + 1) + ": " +
                       what);
    }
    posed = true;
  }
  if (!posed) {
    if (config.formulation == Formulation::kKinematic) {
      throw InputError(label +
                       ": formulation kinematic prescribes every joint, and this one has no "
                       "motion; give it a pose drive ({\"joint\": \"" +
                       body.joint.name +
                       "\", \"pose\": {...}}, run_spec.proto Drive.Pose) or use formulation "
                       "joint (or auto)");
    }
    return;
  }
  if (config.formulation == Formulation::kKinematic) return;
  if (config.formulation == Formulation::kAuto && DriveSet(model, config.drives).all_prescribed()) {
    return;
  }
  throw InputError(label +
                   " has a prescribed pose, which runs in formulation kinematic only, where "
                   "every joint is prescribed; prescribe every joint (formulation kinematic or "
                   "auto), or leave this joint passive to simulate its motion");
}

// The initial quaternion at q0[k..k+3]: unit within 1e-6.
void CheckUnitQuaternion(const RunConfig& config, int k, const std::string& label) {
  if (config.q0.size() != 0 && k + 4 <= config.q0.size()) {
    const double* quat = config.q0.data() + k;
    const double norm =
        std::sqrt(quat[0] * quat[0] + quat[1] * quat[1] + quat[2] * quat[2] + quat[3] * quat[3]);
    if (!(std::abs(norm - 1.0) <= 1e-6)) {
      throw InputError(FormatString(
          "%s: initial_q's quaternion (qw qx qy qz) = (%g, %g, %g, %g) has norm %.9g; give a "
          "unit quaternion (norm 1 within 1e-6)",
          label.c_str(), quat[0], quat[1], quat[2], quat[3], norm));
    }
  }
}

// initial_bodies: each a free body's, its quaternion unit within 1e-6 (the spec's edge says
// the same with the field's path; this covers a RunConfig built in code).
void CheckInitialBodies(const Model& model, const RunConfig& config) {
  for (const InitialBodyState& state : config.initial_bodies) {
    if (FindFreeBody(model, state.name) < 0) {
      throw InputError("initial_bodies: '" + state.name +
                       "' is no free body of the model; give a free joint's name, as the "
                       "model's position names show it (NAME of NAME.x ... NAME.qz)");
    }
    if (state.quaternion && !(std::abs(state.quaternion->norm() - 1.0) <= 1e-6)) {
      throw InputError(FormatString(
          "initial_bodies '%s': the quaternion has norm %.9g; give a unit quaternion (norm 1 "
          "within 1e-6)",
          state.name.c_str(), state.quaternion->norm()));
    }
  }
}

}  // namespace

void RefuseFreeBodies(const Model& model, const std::string& what) {
  if (!model.has_free_bodies()) return;
  const Body& body = model.bodies[model.free_bodies.front()];
  throw InputError(FreeJointLabel(body) + AndMore(model.free_bodies.size()) + ": " + what);
}

void RefuseBallJoints(const Model& model, const std::string& what) {
  if (!model.has_ball_joints()) return;
  const Body& body = model.bodies[model.ball_bodies.front()];
  throw InputError(BallJointLabel(body) + AndMore(model.ball_bodies.size()) + ": " + what);
}

void CheckFreeBodies(const Model& model, const RunConfig& config) {
  CheckInitialBodies(model, config);
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
  CheckCoordinateCounts(model, config);
  for (const int i : model.free_bodies) {
    const Body& body = model.bodies[i];
    CheckPoseDrives(model, body, config, FreeJointLabel(body),
                    "a free joint has no actuator; leave its drives out (passive), or "
                    "prescribe its motion with a pose drive in a kinematic run");
    if (config.q0.size() == model.nq()) {
      CheckUnitQuaternion(config, body.q_index + 3, FreeJointLabel(body));
    }
  }
}

void CheckBallJoints(const Model& model, const RunConfig& config) {
  if (!model.has_ball_joints()) return;
  if (IsBodyFormulation(config.formulation)) {
    RefuseBallJoints(model, std::string("formulation ") + FormulationName(config.formulation) +
                                " does not simulate ball joints yet; use formulation joint "
                                "(or auto)");
  }
  if (config.target.any()) {
    RefuseBallJoints(model,
                     "an accuracy target does not choose the method for ball joints yet; give "
                     "method and tolerances (e.g. bdf, rtol 1e-8)");
  }
  CheckCoordinateCounts(model, config);
  for (const int i : model.ball_bodies) {
    const Body& body = model.bodies[i];
    CheckPoseDrives(model, body, config, BallJointLabel(body),
                    "a ball joint has no actuator yet; leave its drives out (passive), "
                    "prescribe its orientation with a pose drive in a kinematic run, or model "
                    "the joint as three revolute joints to drive it");
    if (config.q0.size() == model.nq()) {
      CheckUnitQuaternion(config, body.q_index, BallJointLabel(body));
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
  CheckBallJoints(model, config);
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
}

// sensor_points: on links of the model, in a run whose states carry them (external drives).
void CheckSensorPoints(const Model& model, const RunConfig& config, const DriveSet& drives) {
  if (config.sensor_points.empty()) return;
  if (drives.external_joints().empty()) {
    throw InputError(
        "sensor_points: only a run with external drives sends states (Simulation.Control) to "
        "carry them; give a drive {\"external\": {...}} or drop sensor_points");
  }
  for (size_t i = 0; i < config.sensor_points.size(); ++i) {
    const std::string& link = config.sensor_points[i].link;
    if (model.FindFrame(link) >= 0) continue;
    std::string names;
    int listed = 0;
    for (const Frame& frame : model.frames) {
      if (++listed > 20) {
        names += ", ...";
        break;
      }
      names += (names.empty() ? "'" : ", '") + frame.name + "'";
    }
    throw InputError("sensor_points[" + std::to_string(i) +
                     "].link: the model has no link named '" + link.substr(0, 64) +
                     "'; give one of " + names);
  }
}

FormulationChoice ValidateRun(const Model& model, const RunConfig& config, const DriveSet& drives) {
  CheckShape(model, config);
  CheckFreeBodies(model, config);
  CheckBallJoints(model, config);
  CheckContact(model, config);
  const FormulationChoice choice = ChooseFormulation(config, drives);
  if (choice.formulation != Formulation::kJoint &&
      choice.formulation != Formulation::kKinematic) {  // auto's choice too
    RefuseBallJoints(
        model,
        std::string("formulation ") + FormulationName(choice.formulation) +
            " does not simulate ball joints yet; use formulation joint (or kinematic, with a "
            "pose drive on each ball joint)");
  }
  CheckSampledDrives(model, config, drives, choice);
  CheckSensorPoints(model, config, drives);
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
