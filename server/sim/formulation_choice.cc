#include "server/sim/formulation_choice.h"

#include "server/common/check.h"

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
    case Formulation::kBodyIndex2:
    case Formulation::kBodyBaumgarte:
      throw InputError(std::string("formulation ") + FormulationName(config.formulation) +
                       " (body coordinates) is not available in this version; use joint or "
                       "auto");
  }
  MBSTREAM_CHECK_MSG(false, "unknown formulation");
  return {};
}

}  // namespace mbstream
