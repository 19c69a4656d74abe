#include "server/parse/urdf_mimic.h"

#include <cmath>
#include <string>

#include "shared/common/check.h"

namespace mbstream {

namespace {

// The body a moving joint named `name` moves, or -1.
int BodyOfJoint(const Model& model, const std::string& name) {
  for (int i = 0; i < model.num_dofs(); ++i) {
    if (model.bodies[i].joint.name == name) return i;
  }
  return -1;
}

}  // namespace

std::vector<LoopClosure> MimicCouplings(const std::vector<urdf::JointConstSharedPtr>& joints,
                                        const Model& model, bool couple,
                                        const UrdfDiagnostics& diagnostics) {
  std::vector<LoopClosure> couplings;
  for (const urdf::JointConstSharedPtr& joint : joints) {
    if (joint->mimic == nullptr) continue;
    const urdf::JointMimic& mimic = *joint->mimic;
    const std::string where = diagnostics.Joint(joint->name);
    const int follower = BodyOfJoint(model, joint->name);  // -1: a fixed joint
    if (!couple) {
      diagnostics.Warn(where + ": <mimic> of joint '" + mimic.joint_name + "' is ignored; " +
                       (follower < 0 ? std::string("the joint is fixed; remove the <mimic>")
                                     : "the joint moves as a degree of freedom of its own "
                                       "(submit or simulate with --couple-mimic to hold it to '" +
                                           mimic.joint_name + "')"));
      continue;
    }
    if (follower < 0) {
      throw InputError(where + ": a fixed joint cannot follow joint '" + mimic.joint_name +
                       "' (<mimic>); remove the <mimic> or make the joint revolute or prismatic");
    }
    const int leader = BodyOfJoint(model, mimic.joint_name);
    if (leader < 0 || leader == follower) {
      throw InputError(where + ": <mimic joint=\"" + mimic.joint_name + "\">: " +
                       (leader == follower ? std::string("a joint cannot follow itself")
                                           : "the model has no moving joint of that name") +
                       "; name another revolute, continuous or prismatic joint");
    }
    if (!std::isfinite(mimic.multiplier) || !std::isfinite(mimic.offset)) {
      throw InputError(where + ": <mimic> multiplier " + FormatNumber(mimic.multiplier) +
                       " and offset " + FormatNumber(mimic.offset) +
                       " must be finite; give numbers");
    }
    LoopClosure coupling;
    coupling.name = joint->name;
    coupling.where = diagnostics.JointLine(joint->name);
    coupling.type = LoopJointType::kMimic;
    coupling.body_a = leader;
    coupling.body_b = follower;
    coupling.multiplier = mimic.multiplier;
    coupling.offset = mimic.offset;
    couplings.push_back(coupling);
  }
  return couplings;
}

}  // namespace mbstream
