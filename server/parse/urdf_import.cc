#include "server/parse/urdf_import.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <vector>

#include "server/model/model_builder.h"
#include "server/parse/collision_reading.h"
#include "server/parse/import_cancel.h"
#include "server/parse/urdf_convert.h"
#include "server/parse/urdf_diagnostics.h"
#include "server/parse/urdf_meshes.h"
#include "server/parse/urdf_mimic.h"
#include "server/parse/urdf_xml_scan.h"
#include "server/parse/urdfdom_parse.h"
#include "shared/common/check.h"
#include "shared/model_files/joint_order.h"
#include "shared/model_files/tcp_choice.h"

namespace mbstream {

namespace {

using JointList = std::vector<urdf::JointConstSharedPtr>;

// The joints in the shared reading's order (shared/model_files/joint_order.h); joints that
// cannot be placed close a loop.
JointList JointsParentFirst(const urdf::ModelInterface& urdf, const UrdfXmlFacts& facts,
                            const UrdfDiagnostics& diagnostics) {
  MBSTREAM_CHECK(facts.joint_order.size() == urdf.joints_.size());
  model_files::JointOrder order = model_files::OrderJoints(urdf, facts.joint_order);
  MBSTREAM_CHECK_MSG(order.ordered.size() + order.unplaced.size() == urdf.joints_.size(),
                     "urdfdom lost a joint");
  if (!order.unplaced.empty()) {
    const auto& pending = order.unplaced;
    std::string names;
    for (const auto& joint : pending) names += (names.empty() ? "'" : ", '") + joint->name + "'";
    throw InputError(diagnostics.Joint(pending.front()->name) + ": its parent link '" +
                     pending.front()->parent_link_name + "' is not connected to the root " +
                     "link '" + urdf.getRoot()->name + "': joints " + names + " form a closed " +
                     "loop, and mbstream simulates trees only; remove a joint to open the loop");
  }
  return std::move(order.ordered);
}

// The TCP link (shared/model_files/tcp_choice.h); "" with a warning when there is none.
std::string ChooseTcp(const urdf::ModelInterface& urdf, const JointList& joints,
                      const UrdfXmlFacts& facts, const UrdfDiagnostics& diagnostics) {
  model_files::JointOrder order;
  order.ordered = joints;
  const std::string tcp = model_files::ChooseTcpLink(urdf, order, facts.link_order);
  if (!tcp.empty()) return tcp;
  const std::string last_body = model_files::LastMovingLink(order);
  diagnostics.Warn(diagnostics.source() + ": the model has no TCP: no link is named 'tcp' or " +
                   "'tool0', and no leaf link hangs on a fixed joint from the last moving " +
                   "link" + (last_body.empty() ? "" : " '" + last_body + "'") +
                   "; add a link 'tcp' on a fixed joint at the tool centre point");
  return "";
}

// Runs a ModelBuilder call; its InputErrors (which the checks above should pre-empt) get
// the file name.
template <typename Call>
void Guarded(const std::string& source, Call call) {
  try {
    call();
  } catch (const InputError& e) {
    throw InputError(source + ": " + e.what());
  }
}

// The world a --floating-base model's root moves in.
constexpr char kFloatingBaseWorld[] = "world";

// --floating-base: the root link moves freely, by a free joint named after it.
void AddFloatingRoot(const urdf::Link& root, const UrdfDiagnostics& diagnostics,
                     ModelBuilder* builder) {
  if (root.name == kFloatingBaseWorld) {
    throw InputError(diagnostics.Link(root.name) +
                     ": --floating-base: the root link is 'world' already (a 'floating' joint "
                     "from it frees the base); drop --floating-base");
  }
  const RigidInertia inertia = ConvertInertia(root, root.name, diagnostics);
  Guarded(diagnostics.source(),
          [&] { builder->AddFreeLink(root.name, root.name, Pose::Identity(), inertia); });
}

// A 'floating' joint: a free joint of its child, which starts at the joint's <origin>; only
// from the root link (the world), as a free joint exists only at the root of a tree.
void AddFloatingJoint(const urdf::Joint& joint, const urdf::Link& child, const std::string& root,
                      bool floating_base, const UrdfDiagnostics& diagnostics,
                      ModelBuilder* builder) {
  if (joint.parent_link_name != root || floating_base) {
    throw InputError(diagnostics.Joint(joint.name) + ": a 'floating' joint's parent must be the " +
                     "root link '" + root + "' (the world), not '" + joint.parent_link_name +
                     (floating_base ? "' (with --floating-base the root moves itself)" : "'") +
                     "; make it fixed, revolute or prismatic, or give it the root as parent");
  }
  const RigidInertia inertia = ConvertInertia(child, joint.name, diagnostics);
  const Pose X_WL = ToPose(joint.parent_to_joint_origin_transform);
  Guarded(diagnostics.source(),
          [&] { builder->AddFreeLink(child.name, joint.name, X_WL, inertia); });
}

}  // namespace

UrdfImport ImportUrdf(const std::string& text, const std::string& source,
                      const std::set<std::string>& assets, const UrdfImportOptions& options) {
  UrdfImport result;
  const UrdfXmlFacts facts = ScanUrdfXml(text, source, &result.warnings, options.max_links);
  ThrowIfImportCancelled();  // between the stages, and every 256 joints (import_cancel.h)
  result.mesh_files = facts.mesh_files;
  const UrdfDiagnostics diagnostics(source, facts.link_lines, facts.joint_lines, &result.warnings,
                                    options.repair);
  const std::shared_ptr<urdf::ModelInterface> urdf =
      ParseWithUrdfdom(facts.urdfdom_text, diagnostics);
  ThrowIfImportCancelled();
  const JointList joints = JointsParentFirst(*urdf, facts, diagnostics);
  ImportCancelPoll poll;

  MissingMeshes missing_meshes;
  CheckMeshes(*urdf->getRoot(), assets, diagnostics, &missing_meshes);
  const std::string& root = urdf->getRoot()->name;
  ModelBuilder builder(urdf->getName(), options.floating_base ? kFloatingBaseWorld : root);
  if (options.floating_base) AddFloatingRoot(*urdf->getRoot(), diagnostics, &builder);
  for (const auto& joint : joints) {
    poll.Tick();
    const urdf::Link& child = *urdf->getLink(joint->child_link_name);
    CheckMeshes(child, assets, diagnostics, &missing_meshes);
    if (joint->type == urdf::Joint::FLOATING) {
      AddFloatingJoint(*joint, child, root, options.floating_base, diagnostics, &builder);
    } else if (joint->type == urdf::Joint::FIXED) {
      const Pose X_PL = ToPose(joint->parent_to_joint_origin_transform);
      const RigidInertia inertia = ConvertInertia(child, "", diagnostics);
      Guarded(source,
              [&] { builder.AddFixedLink(child.name, joint->parent_link_name, X_PL, inertia); });
    } else {
      const auto rotor = facts.rotor_inertia.find(joint->name);
      const Joint converted = ConvertJoint(
          *joint, rotor == facts.rotor_inertia.end() ? 0.0 : rotor->second, diagnostics);
      const RigidInertia inertia = ConvertInertia(child, joint->name, diagnostics);
      Guarded(source, [&] {
        builder.AddMovingLink(child.name, joint->parent_link_name, converted, inertia);
      });
    }
  }
  WarnMissingMeshes(missing_meshes, diagnostics);
  const std::string tcp = ChooseTcp(*urdf, joints, facts, diagnostics);
  if (!tcp.empty()) Guarded(source, [&] { builder.SetTcp(tcp); });
  ThrowIfImportCancelled();
  result.model = builder.Build();
  ReadUrdfCollisions(text, source, options.collision_meshes, &result.model, &result.warnings);
  result.loops = MimicCouplings(joints, result.model, options.couple_mimic, diagnostics);
  const int links = static_cast<int>(result.model.frames.size());
  if (options.max_links > 0 && links > options.max_links) {
    throw LimitError(source + ": the model has " + std::to_string(links) +
                     " links and points, more than the limit of " +
                     std::to_string(options.max_links) + " (--max-links); raise the limit");
  }
  if (result.model.num_dofs() == 0) {
    diagnostics.Warn(source + ": the model has no moving joints; nothing will move");
  }
  return result;
}

UrdfImport ImportUrdfFile(const std::string& path, const UrdfImportOptions& options) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw InputError(path + ": is a directory; give the path of a .urdf file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(path + ": cannot open the file (" + std::strerror(errno) +
                     "); check the path");
  }
  std::ostringstream contents;
  contents << in.rdbuf();
  const std::string text = contents.str();
  std::vector<std::string> ignored;  // ImportUrdf warns again
  const UrdfXmlFacts facts = ScanUrdfXml(text, path, &ignored, options.max_links);
  const std::set<std::string> assets =
      ExistingMeshFiles(facts.mesh_files, std::filesystem::path(path).parent_path());
  UrdfImportOptions local = options;
  if (!local.collision_meshes) {
    local.collision_meshes = DiskMeshSource(std::filesystem::path(path).parent_path());
  }
  return ImportUrdf(text, path, assets, local);
}

}  // namespace mbstream
