// The spanning tree of an SDFormat file's models, their link frames and joint axes.
#include <deque>
#include <map>

#include <sdf/JointAxis.hh>
#include <sdf/Link.hh>

#include "shared/common/check.h"
#include "shared/model_files/sdf_reading.h"

namespace mbstream::model_files {

namespace {

std::string Scoped(const SdfModelEntry& entry, const std::string& name) {
  return name == kSdfWorld ? name : entry.prefix + name;
}

void CheckJointType(const SdfJointOutline& info) {
  switch (info.joint->Type()) {
    case sdf::JointType::REVOLUTE:
    case sdf::JointType::CONTINUOUS:
    case sdf::JointType::PRISMATIC:
    case sdf::JointType::FIXED:
    case sdf::JointType::BALL:
      return;
    default:
      throw InputError(info.where + ": joint '" + info.name +
                       "': this joint type is not simulated by mbstream; use revolute, "
                       "continuous, prismatic, fixed or ball joints (a model with no joint to "
                       "the world moves freely)");
  }
}

// The file's joints (those of static models only warned of), then each model's free joint
// or welds.
void OutlineJoints(const SdfFile& file, SdfTree* tree) {
  const std::vector<SdfModelEntry>& models = file.models();
  for (size_t m = 0; m < models.size(); ++m) {
    const SdfModelEntry& entry = models[m];
    for (uint64_t k = 0; k < entry.model->JointCount(); ++k) {
      const sdf::Joint* joint = entry.model->JointByIndex(k);
      SdfJointOutline info{joint,
                           SdfJointRole::kFile,
                           entry.prefix + joint->Name(),
                           Scoped(entry, joint->ParentLinkName()),
                           Scoped(entry, joint->ChildLinkName()),
                           file.Where(joint->Element()),
                           static_cast<int>(m)};
      if (entry.is_static) {
        tree->warnings.push_back(info.where + ": joint '" + info.name +
                                 "' moves nothing: its model is static (welded to the world "
                                 "where it stands); drop <static> to let it move");
        continue;
      }
      for (const std::string* link : {&info.parent, &info.child}) {
        if (*link != kSdfWorld && FindSdfLink(file, *link).link == nullptr) {
          throw InputError(info.where + ": joint '" + info.name + "': link '" + *link +
                           "' is not a link of model '" + entry.model->Name() +
                           "'; name a link of this model (or world)");
        }
      }
      CheckJointType(info);
      tree->joints.push_back(std::move(info));
    }
  }
  for (size_t m = 0; m < models.size(); ++m) {
    const SdfModelEntry& entry = models[m];
    if (entry.is_static) {
      for (uint64_t l = 0; l < entry.model->LinkCount(); ++l) {
        const sdf::Link& link = *entry.model->LinkByIndex(l);
        const std::string name = entry.prefix + link.Name();
        tree->joints.push_back({nullptr, SdfJointRole::kWeld, name, kSdfWorld, name,
                                file.Where(link.Element()), static_cast<int>(m)});
      }
      continue;
    }
    if (entry.top != static_cast<int>(m)) continue;  // a nested model moves with its holder
    bool to_world = false;
    for (const SdfJointOutline& info : tree->joints) {
      if (info.role == SdfJointRole::kFile && info.parent == kSdfWorld &&
          models[info.model].top == static_cast<int>(m)) {
        to_world = true;
      }
    }
    const auto [canonical, relative] = entry.model->CanonicalLinkAndRelativeName();
    if (to_world || canonical == nullptr) continue;
    const std::string name = entry.prefix + relative;
    tree->joints.push_back({nullptr, SdfJointRole::kFree, name, kSdfWorld, name,
                            file.Where(entry.model->Element()), static_cast<int>(m)});
  }
}

}  // namespace

SdfTree ChooseSdfTree(const SdfFile& file) {
  SdfTree tree;
  OutlineJoints(file, &tree);
  const std::vector<SdfModelEntry>& models = file.models();
  std::map<std::string, bool> reached{{kSdfWorld, true}};
  std::vector<bool> cut(tree.joints.size(), false);
  for (size_t top = 0; top < models.size(); ++top) {
    if (models[top].top != static_cast<int>(top)) continue;
    std::deque<std::string> queue{kSdfWorld};
    while (!queue.empty()) {
      const std::string link = queue.front();
      queue.pop_front();
      for (size_t j = 0; j < tree.joints.size(); ++j) {
        const SdfJointOutline& info = tree.joints[j];
        if (info.parent != link) continue;
        if (link == kSdfWorld && models[info.model].top != static_cast<int>(top)) continue;
        if (reached[info.child]) {
          cut[j] = true;
          continue;
        }
        reached[info.child] = true;
        tree.tree.push_back(j);
        queue.push_back(info.child);
      }
    }
  }
  for (const SdfModelEntry& entry : models) {
    for (uint64_t k = 0; k < entry.model->LinkCount(); ++k) {
      const sdf::Link* link = entry.model->LinkByIndex(k);
      if (!reached[entry.prefix + link->Name()]) {
        throw InputError(file.Where(link->Element()) + ": link '" + entry.prefix + link->Name() +
                         "' is not reached from the world through parent-to-child joints (a "
                         "model's canonical link with no joint to the world moves freely, but "
                         "its other links need joints); attach it, e.g. with a fixed joint");
      }
    }
  }
  for (size_t j = 0; j < tree.joints.size(); ++j) {
    const SdfJointOutline& info = tree.joints[j];
    if (!reached[info.parent]) {
      throw InputError(info.where + ": joint '" + info.name + "': its parent link '" + info.parent +
                       "' is not reached from the world; attach it");
    }
    if (cut[j]) tree.cut.push_back(j);
  }
  return tree;
}

std::string SdfBallValueName(const std::string& joint, int value) {
  MBSTREAM_CHECK(value >= 0 && value < 4);
  static constexpr const char* kSuffix[4] = {".qw", ".qx", ".qy", ".qz"};
  return joint + kSuffix[value];
}

std::vector<SdfLinkFrame> SdfLinkFrames(const SdfFile& file, const SdfTree& tree) {
  std::vector<SdfLinkFrame> frames;
  for (const size_t j : tree.tree) {
    const SdfJointOutline& info = tree.joints[j];
    SdfLinkFrame frame;
    frame.link = info.child;
    if (info.role != SdfJointRole::kFile || info.joint->Type() == sdf::JointType::FIXED) {
      frame.X_WL = SdfLinkPose(file, info.child);
    } else {
      frame.X_WL = WorldPose(file.models()[info.model], info.joint->SemanticPose(),
                             "joint '" + info.name + "'", info.where);
    }
    frames.push_back(std::move(frame));
  }
  return frames;
}

Eigen::Vector3d SdfJointAxis(const SdfFile& file, const SdfJointOutline& joint,
                             const Eigen::Isometry3d& X_WJ) {
  MBSTREAM_CHECK(joint.joint != nullptr);
  const sdf::JointAxis* axis = joint.joint->Axis(0);
  if (axis == nullptr) {
    throw InputError(joint.where + ": joint '" + joint.name +
                     "': no <axis>; give <axis><xyz>0 0 1</xyz></axis>");
  }
  ignition::math::Vector3d xyz;
  const sdf::Errors errors = axis->ResolveXyz(xyz, "__model__");
  if (!errors.empty()) ThrowSdfErrors(file.source(), errors);
  const Eigen::Vector3d a_W =
      file.models()[joint.model].X_WM.linear() * Eigen::Vector3d(xyz.X(), xyz.Y(), xyz.Z());
  const Eigen::Vector3d a = X_WJ.linear().transpose() * a_W;
  if (!(a.norm() > 1e-12)) {
    throw InputError(joint.where + ": joint '" + joint.name +
                     "': the axis is zero; give a unit vector");
  }
  return a.normalized();
}

}  // namespace mbstream::model_files
