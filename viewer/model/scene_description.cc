#include "viewer/model/scene_description.h"

#include <numbers>
#include <stdexcept>

#include "shared/common/check.h"

namespace mbstream::viewer {

std::vector<double> ScriptUnitsToSi(const KinematicChain& chain, std::span<const double> values) {
  if (static_cast<int>(values.size()) != chain.dof()) {
    throw InputError("the scene has " + std::to_string(chain.dof()) + " joints but " +
                     std::to_string(values.size()) + " joint values were given");
  }
  std::vector<double> si(values.begin(), values.end());
  for (int i = 0; i < chain.dof(); ++i) {
    si[i] *=
        chain.dof_joint(i).kind == ChainJointKind::kRevolute ? std::numbers::pi / 180.0 : 0.001;
  }
  return si;
}

}  // namespace mbstream::viewer
