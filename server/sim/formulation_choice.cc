#include "server/sim/formulation_choice.h"

#include "server/integrate/failure_messages.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

bool AnyVelocitySource(const DriveSet& drives) {
  for (int i = 0; i < drives.size(); ++i) {
    if (drives.velocity_source(i)) return true;
  }
  return false;
}

}  // namespace

FormulationChoice ChooseFormulation(const RunConfig& config, const DriveSet& drives) {
  const std::string torques =
      config.want_torques ? "; drive torques by inverse dynamics (RNEA) at each output" : "";
  switch (config.formulation) {
    case Formulation::kAuto:
      if (drives.all_prescribed()) {
        return {Formulation::kKinematic,
                "auto: every joint is prescribed, so the states are known in closed form and "
                "nothing is integrated" +
                    torques +
                    (AnyVelocitySource(drives)
                         ? " (velocity-source drives are integrated only with formulation joint)"
                         : "")};
      }
      return {Formulation::kJoint,
              "auto: " + std::to_string(drives.size() - drives.num_prescribed()) +
                  " joint(s) move freely, so the joint-space ODE (2n states, minimal "
                  "coordinates) is integrated"};
    case Formulation::kKinematic:
      if (!drives.all_prescribed()) {
        throw InputError(
            "formulation kinematic needs every joint prescribed, but " +
            std::to_string(drives.size() - drives.num_prescribed()) +
            " joint(s) are not; use formulation joint (or auto) to integrate their motion");
      }
      return {Formulation::kKinematic,
              "requested: closed-form states, nothing integrated" + torques};
    case Formulation::kJoint:
      return {Formulation::kJoint, "requested: joint-space ODE, 2n states"};
    case Formulation::kBodyIndex3:
    case Formulation::kBodyIndex2: {
      const std::string name = FormulationName(config.formulation);
      if (config.method != Method::kIda) {
        throw InputError("formulation " + name +
                         " (body coordinates, a differential-algebraic system) needs method "
                         "ida, not " +
                         MethodName(config.method) +
                         "; for an ODE method use formulation body-baumgarte or joint");
      }
      const bool index3 = config.formulation == Formulation::kBodyIndex3;
      return {config.formulation,
              "requested: body coordinates (every link a free body, joints as constraints "
              "with Lagrange multipliers), " +
                  std::string(index3 ? "position-level constraints (index-3 DAE)"
                                     : "velocity-level constraints (index-2 DAE; the "
                                       "position drift is measured)") +
                  ", solved by IDA with a sparse (KLU) Jacobian"};
    }
    case Formulation::kBodyBaumgarte:
      if (config.method == Method::kIda) {
        throw InputError(
            "formulation body-baumgarte is an ODE (acceleration-level constraints with "
            "Baumgarte stabilisation), and method ida is for DAEs: use an ODE method such as "
            "bdf, or formulation body-index2 with ida");
      }
      return {Formulation::kBodyBaumgarte,
              FormatString("requested: body coordinates with acceleration-level constraints and "
                           "Baumgarte stabilisation (alpha = %g 1/s, beta = %g 1/s^2), an ODE; "
                           "the constraint drift is measured",
                           config.baumgarte.alpha, config.baumgarte.beta)};
  }
  MBSTREAM_CHECK_MSG(false, "unknown formulation");
  return {};
}

}  // namespace mbstream
