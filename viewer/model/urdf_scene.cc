#include "viewer/model/urdf_scene.h"

#include <urdf_parser/urdf_parser.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "viewer/model/shape_mesh.h"

namespace mbstream::viewer {

namespace {

constexpr int kResolution = 32;

Eigen::Isometry3d ToIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  t.linear() =
      Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
          .normalized()
          .toRotationMatrix();
  return t;
}

// Joint names in document order.
std::vector<std::string> JointsInDocumentOrder(const std::string& text) {
  static const std::regex kJoint(R"(<joint\s[^>]*?name\s*=\s*["']([^"']+)["'])");
  std::vector<std::string> names;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), kJoint);
       it != std::sregex_iterator(); ++it) {
    names.push_back((*it)[1].str());
  }
  return names;
}

std::filesystem::path FindMesh(const std::string& filename, const std::filesystem::path& dir) {
  std::string rest = filename;
  std::vector<std::filesystem::path> candidates;
  for (const std::string prefix : {"file://", "package://"}) {
    if (rest.rfind(prefix, 0) == 0) rest = rest.substr(prefix.size());
  }
  const std::filesystem::path as_written(rest);
  candidates.push_back(as_written.is_absolute() ? as_written : dir / as_written);
  if (filename.rfind("package://", 0) == 0 && rest.find('/') != std::string::npos) {
    candidates.push_back(dir / rest.substr(rest.find('/') + 1));
  }
  candidates.push_back(dir / std::filesystem::path(rest).filename());
  for (const auto& candidate : candidates) {
    std::error_code error;
    if (std::filesystem::is_regular_file(candidate, error)) return candidate;
  }
  return {};
}

class UrdfSceneBuilder {
 public:
  UrdfSceneBuilder(const std::string& source, std::filesystem::path dir)
      : source_(source), dir_(std::move(dir)) {}

  SceneDescription Build(const std::string& text) {
    const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text);
    if (!model || !model->getRoot()) {
      Fail(
          "urdfdom could not read the robot description (its messages are printed above); "
          "fix the XML or URDF structure");
    }
    SceneDescription scene;
    scene.title = model->getName();
    const std::string root = model->getRoot()->name;
    frame_of_link_[root] = 0;
    scene.frame_names.push_back(root);

    std::vector<ChainJoint> joints;
    std::vector<std::string> pending = JointsInDocumentOrder(text);
    bool progress = true;
    while (!pending.empty() && progress) {
      progress = false;
      for (auto it = pending.begin(); it != pending.end();) {
        const urdf::JointConstSharedPtr joint = model->getJoint(*it);
        if (!joint) {
          it = pending.erase(it);
          continue;
        }
        const auto parent = frame_of_link_.find(joint->parent_link_name);
        if (parent == frame_of_link_.end()) {
          ++it;
          continue;
        }
        joints.push_back(ChainJointOf(*joint, parent->second));
        frame_of_link_[joint->child_link_name] = static_cast<int>(joints.size());
        scene.frame_names.push_back(joint->child_link_name);
        it = pending.erase(it);
        progress = true;
      }
    }
    scene.chain = KinematicChain(Eigen::Isometry3d::Identity(), std::move(joints));
    scene.initial_q.assign(scene.chain.dof(), 0.0);

    for (const auto& [name, frame] : frame_of_link_) {
      const urdf::LinkConstSharedPtr link = model->getLink(name);
      if (!link) continue;
      for (const urdf::VisualSharedPtr& visual : link->visual_array) {
        if (visual && visual->geometry) AddVisual(name, frame, *visual, &scene.visuals);
      }
      std::string lower = name;
      for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if ((lower == "tcp" || lower == "tool0") && scene.probes.empty()) {
        ProbePoint probe;
        probe.name = "tcp";
        probe.frame = frame;
        probe.refer = 0;
        probe.refer_name = root;
        scene.probes.push_back(probe);
      }
    }
    return scene;
  }

 private:
  [[noreturn]] void Fail(const std::string& message) const {
    throw std::runtime_error(source_ + ": " + message);
  }

  ChainJoint ChainJointOf(const urdf::Joint& joint, int parent) const {
    ChainJoint chain_joint;
    chain_joint.name = joint.name;
    chain_joint.parent = parent;
    chain_joint.pre = ToIsometry(joint.parent_to_joint_origin_transform);
    chain_joint.axis = Eigen::Vector3d(joint.axis.x, joint.axis.y, joint.axis.z);
    switch (joint.type) {
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
        chain_joint.kind = ChainJointKind::kRevolute;
        break;
      case urdf::Joint::PRISMATIC:
        chain_joint.kind = ChainJointKind::kPrismatic;
        break;
      case urdf::Joint::FIXED:
        chain_joint.kind = ChainJointKind::kFixed;
        break;
      default:
        Fail("joint '" + joint.name +
             "': floating and planar joints are not supported; make it fixed, revolute or "
             "prismatic");
    }
    if (chain_joint.kind != ChainJointKind::kFixed && !(chain_joint.axis.norm() > 1e-12)) {
      Fail("joint '" + joint.name + "': the axis is zero; give e.g. <axis xyz=\"0 0 1\"/>");
    }
    return chain_joint;
  }

  void AddVisual(const std::string& link, int frame, const urdf::Visual& visual,
                 std::vector<VisualPart>* out) const {
    VisualPart part;
    part.name = link;
    part.frame = frame;
    part.placement = ToIsometry(visual.origin);
    // urdfdom leaves a material without <color> black: keep the default grey then.
    if (visual.material) {
      const urdf::Color& c = visual.material->color;
      if (c.r > 0 || c.g > 0 || c.b > 0) part.color = Eigen::Vector3d(c.r, c.g, c.b);
    }
    const urdf::Geometry& geometry = *visual.geometry;
    switch (geometry.type) {
      case urdf::Geometry::BOX: {
        const auto& box = static_cast<const urdf::Box&>(geometry);
        const Eigen::Vector3d size(box.dim.x, box.dim.y, box.dim.z);
        part.geometry = CubeMesh({size});
        part.placement = part.placement * Eigen::Translation3d(-size / 2);
        break;
      }
      case urdf::Geometry::CYLINDER: {
        const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
        part.geometry = CylinderMesh({2 * cylinder.radius, kResolution, cylinder.length});
        part.placement = part.placement * Eigen::Translation3d(0, 0, -cylinder.length / 2);
        break;
      }
      case urdf::Geometry::SPHERE: {
        const auto& sphere = static_cast<const urdf::Sphere&>(geometry);
        part.geometry = SphereMesh({sphere.radius, kResolution});
        break;
      }
      case urdf::Geometry::MESH: {
        const auto& mesh = static_cast<const urdf::Mesh&>(geometry);
        std::string extension = std::filesystem::path(mesh.filename).extension().string();
        for (char& c : extension)
          c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (extension != ".stl") {
          Fail("link '" + link + "': mesh '" + mesh.filename +
               "' is not STL; convert it to STL (the viewer reads STL meshes only)");
        }
        const std::filesystem::path path = FindMesh(mesh.filename, dir_);
        if (path.empty()) {
          Fail("link '" + link + "': mesh '" + mesh.filename + "' not found (looked in " +
               dir_.string() + "); put the file beside the URDF");
        }
        part.geometry = StlGeometry{path};
        part.scale = Eigen::Vector3d(mesh.scale.x, mesh.scale.y, mesh.scale.z);
        break;
      }
      default:
        return;
    }
    out->push_back(std::move(part));
  }

  std::string source_;
  std::filesystem::path dir_;
  std::map<std::string, int> frame_of_link_;
};

}  // namespace

SceneDescription SceneFromUrdf(const std::string& text, const std::string& source,
                               const std::filesystem::path& asset_directory) {
  return UrdfSceneBuilder(source, asset_directory).Build(text);
}

SceneDescription SceneFromUrdfFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code error;
  if (!in || !std::filesystem::is_regular_file(path, error)) {
    throw std::runtime_error(path.string() + ": cannot read the URDF file; check the path");
  }
  std::ostringstream text;
  text << in.rdbuf();
  return SceneFromUrdf(text.str(), path.string(), path.parent_path());
}

}  // namespace mbstream::viewer
