#include "server/parse/urdf_import.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <vector>

#include "server/common/check.h"
#include "server/model/model_builder.h"
#include "server/parse/urdf_convert.h"
#include "server/parse/urdf_diagnostics.h"
#include "server/parse/urdf_meshes.h"
#include "server/parse/urdf_xml_scan.h"
#include "server/parse/urdfdom_parse.h"

namespace mbstream {

namespace {

using JointList = std::vector<urdf::JointConstSharedPtr>;

// The joints parents first: in document order, except that a joint waits until its parent
// link is placed. This keeps the URDF's joint order (the model's degree-of-freedom order)
// whenever the file lists parents first, as most do.
JointList JointsParentFirst(const urdf::ModelInterface& urdf, const UrdfXmlFacts& facts,
                            const UrdfDiagnostics& diagnostics) {
  const std::string& root = urdf.getRoot()->name;
  std::set<std::string> placed = {root};
  JointList pending;
  for (const std::string& name : facts.joint_order) {
    pending.push_back(urdf.getJoint(name));
    MBSTREAM_CHECK_MSG(pending.back() != nullptr, "urdfdom lost joint '" + name + "'");
  }
  MBSTREAM_CHECK(pending.size() == urdf.joints_.size());
  JointList ordered;
  while (!pending.empty()) {
    const auto ready = std::find_if(pending.begin(), pending.end(), [&](const auto& joint) {
      return placed.count(joint->parent_link_name) != 0;
    });
    if (ready == pending.end()) {
      std::string names;
      for (const auto& joint : pending) names += (names.empty() ? "'" : ", '") + joint->name + "'";
      throw InputError(diagnostics.Joint(pending.front()->name) + ": its parent link '" +
                       pending.front()->parent_link_name + "' is not connected to the root " +
                       "link '" + root + "': joints " + names + " form a closed loop, and " +
                       "mbstream simulates trees only; remove a joint to open the loop");
    }
    placed.insert((*ready)->child_link_name);
    ordered.push_back(*ready);
    pending.erase(ready);
  }
  return ordered;
}

std::string Lowercase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The TCP link: "tcp" (any case), else "tool0", else the first leaf link on a fixed joint
// of the last moving body; "" (with a warning) when there is none.
std::string ChooseTcp(const urdf::ModelInterface& urdf, const JointList& joints,
                      const UrdfXmlFacts& facts, const UrdfDiagnostics& diagnostics) {
  for (const std::string& name : facts.link_order) {
    if (Lowercase(name) == "tcp") return name;
  }
  if (facts.link_lines.count("tool0") != 0) return "tool0";

  std::map<std::string, std::string> body_of = {{urdf.getRoot()->name, ""}};  // link -> body
  std::string last_body;
  for (const auto& joint : joints) {
    const bool fixed = joint->type == urdf::Joint::FIXED;
    body_of[joint->child_link_name] =
        fixed ? body_of[joint->parent_link_name] : joint->child_link_name;
    if (!fixed) last_body = joint->child_link_name;
  }
  for (const auto& joint : joints) {
    const std::string& link = joint->child_link_name;
    if (!last_body.empty() && joint->type == urdf::Joint::FIXED && body_of[link] == last_body &&
        urdf.getLink(link)->child_joints.empty()) {
      return link;
    }
  }
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

}  // namespace

UrdfImport ImportUrdf(const std::string& text, const std::string& source,
                      const std::set<std::string>& assets, const UrdfImportOptions& options) {
  UrdfImport result;
  const UrdfXmlFacts facts = ScanUrdfXml(text, source, &result.warnings);
  result.mesh_files = facts.mesh_files;
  const UrdfDiagnostics diagnostics(source, facts.link_lines, facts.joint_lines, &result.warnings,
                                    options.repair);
  const std::shared_ptr<urdf::ModelInterface> urdf =
      ParseWithUrdfdom(facts.urdfdom_text, diagnostics);
  const JointList joints = JointsParentFirst(*urdf, facts, diagnostics);

  CheckMeshes(*urdf->getRoot(), assets, diagnostics);
  ModelBuilder builder(urdf->getName(), urdf->getRoot()->name);
  for (const auto& joint : joints) {
    const urdf::Link& child = *urdf->getLink(joint->child_link_name);
    CheckMeshes(child, assets, diagnostics);
    if (joint->type == urdf::Joint::FIXED) {
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
  const std::string tcp = ChooseTcp(*urdf, joints, facts, diagnostics);
  if (!tcp.empty()) Guarded(source, [&] { builder.SetTcp(tcp); });
  result.model = builder.Build();
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
  const UrdfXmlFacts facts = ScanUrdfXml(text, path, &ignored);
  const std::set<std::string> assets =
      ExistingMeshFiles(facts.mesh_files, std::filesystem::path(path).parent_path());
  return ImportUrdf(text, path, assets, options);
}

}  // namespace mbstream
