#include "viewer/model/urdf_scene.h"

#include <urdf_parser/urdf_parser.h>

#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "shared/common/check.h"
#include "shared/model_files/joint_order.h"
#include "shared/model_files/tcp_choice.h"
#include "shared/model_files/urdf_outline.h"
#include "viewer/model/inertia_box.h"
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

// A box of `size` (m) centred at `centre` in `frame`.
VisualPart BoxPart(const std::string& name, int frame, const Eigen::Vector3d& size,
                   const Eigen::Isometry3d& centre) {
  VisualPart part;
  part.name = name;
  part.frame = frame;
  part.geometry = CubeMesh({size});
  part.placement = centre * Eigen::Translation3d(-size / 2);
  return part;
}

// A free joint's seven values holding its link at X_PL: x y z, qw qx qy qz.
void AppendFreeValues(const Eigen::Isometry3d& X_PL, std::vector<double>* q) {
  const Eigen::Quaterniond rotation(X_PL.linear());
  const Eigen::Vector3d& p = X_PL.translation();
  q->insert(q->end(),
            {p.x(), p.y(), p.z(), rotation.w(), rotation.x(), rotation.y(), rotation.z()});
}

constexpr char kWorld[] = "world";

class UrdfSceneBuilder {
 public:
  UrdfSceneBuilder(const std::string& source, MeshFinder find_mesh, bool floating_base)
      : source_(source), find_mesh_(std::move(find_mesh)), floating_base_(floating_base) {}

  SceneDescription Build(const std::string& text) {
    std::string error;
    const std::optional<model_files::UrdfOutline> outline =
        model_files::ReadUrdfOutline(text, &error);
    if (!outline) Fail(error + "; fix the XML");
    outline_ = &*outline;
    const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(outline->urdfdom_text);
    if (!model || !model->getRoot()) {
      Fail(
          "urdfdom could not read the robot description (its messages are printed above); "
          "fix the XML or URDF structure");
    }
    SceneDescription scene;
    scene.title = model->getName();
    scene.joints_named_as_model = true;
    const std::string root = model->getRoot()->name;
    scene_root_ = root;
    std::vector<ChainJoint> joints;
    if (floating_base_) {
      // The root moves freely in the world (frame 0): a free joint named after it.
      if (root == kWorld) {
        Fail(
            "--floating-base: the root link is 'world' already; its 'floating' joint frees "
            "the base: drop --floating-base");
      }
      scene.frame_names.push_back(kWorld);
      ChainJoint free;
      free.name = root;
      free.kind = ChainJointKind::kFree;
      joints.push_back(free);
      AppendFreeValues(Eigen::Isometry3d::Identity(), &scene.initial_q);
    }
    frame_of_link_[root] = static_cast<int>(joints.size());
    scene.frame_names.push_back(root);

    const model_files::JointOrder order = model_files::OrderJoints(*model, outline->joint_order);
    if (!order.unplaced.empty()) {
      Fail("joint '" + order.unplaced.front()->name + "': its parent link '" +
           order.unplaced.front()->parent_link_name + "' is not connected to the root link '" +
           root + "'; the joints form a loop: remove a joint to open it");
    }
    for (const urdf::JointConstSharedPtr& joint : order.ordered) {
      joints.push_back(ChainJointOf(*joint, frame_of_link_.at(joint->parent_link_name)));
      if (joints.back().kind == ChainJointKind::kFree) {
        // Its values are the child's pose in the root (the world), as the server's.
        AppendFreeValues(ToIsometry(joint->parent_to_joint_origin_transform), &scene.initial_q);
        joints.back().pre = Eigen::Isometry3d::Identity();
      } else if (joints.back().kind != ChainJointKind::kFixed) {
        scene.initial_q.push_back(0.0);
      }
      frame_of_link_[joint->child_link_name] = static_cast<int>(joints.size());
      scene.frame_names.push_back(joint->child_link_name);
    }
    scene.chain = KinematicChain(Eigen::Isometry3d::Identity(), std::move(joints));
    MBSTREAM_CHECK(static_cast<int>(scene.initial_q.size()) == scene.chain.dof());

    for (const std::string& name : scene.frame_names) {
      const urdf::LinkConstSharedPtr link = model->getLink(name);
      if (!link) continue;
      for (const urdf::VisualSharedPtr& visual : link->visual_array) {
        if (visual && visual->geometry) AddVisual(*link, *visual, &scene);
      }
    }
    const std::string tcp = model_files::ChooseTcpLink(*model, order, outline->link_order);
    if (!tcp.empty()) {
      ProbePoint probe;
      probe.name = "tcp";
      probe.frame = frame_of_link_.at(tcp);
      probe.refer = 0;
      probe.refer_name = scene.frame_names[0];
      scene.probes.push_back(probe);
    }
    return scene;
  }

 private:
  [[noreturn]] void Fail(const std::string& message) const {
    throw InputError(source_ + ": " + message);
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
      case urdf::Joint::FLOATING:
        if (parent != 0) {
          Fail("joint '" + joint.name + "': a floating joint's parent must be the root link '" +
               scene_root_ + "' (the world); make it fixed, revolute or prismatic");
        }
        chain_joint.kind = ChainJointKind::kFree;
        return chain_joint;
      default:
        Fail("joint '" + joint.name +
             "': planar joints are not supported; make it fixed, revolute or prismatic");
    }
    if (chain_joint.kind != ChainJointKind::kFixed && !(chain_joint.axis.norm() > 1e-12)) {
      Fail("joint '" + joint.name + "': the axis is zero; give e.g. <axis xyz=\"0 0 1\"/>");
    }
    return chain_joint;
  }

  // The tinted box that stands for a link's missing mesh `filename`: the box of its inertia.
  VisualPart Placeholder(const urdf::Link& link, int frame, const std::string& filename) const {
    InertiaBox box;
    if (link.inertial) {
      const urdf::Inertial& i = *link.inertial;
      Eigen::Matrix3d inertia;
      inertia << i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz;
      box = BoxOfInertia(i.mass, inertia, ToIsometry(i.origin));
    }
    VisualPart part = BoxPart(link.name, frame, box.size, box.pose);
    part.color = kPlaceholderColour;
    part.opacity = kPlaceholderOpacity;
    part.placeholder = true;
    part.mesh_filename = filename;
    return part;
  }

  void AddVisual(const urdf::Link& link, const urdf::Visual& visual, SceneDescription* scene) {
    const int frame = frame_of_link_.at(link.name);
    VisualPart part;
    part.name = link.name;
    part.frame = frame;
    part.placement = ToIsometry(visual.origin);
    // urdfdom leaves a material without <color> black: that is no colour of the author's.
    const bool urdf_colour =
        visual.material && outline_->coloured_materials.count(visual.material_name) != 0;
    if (urdf_colour) {
      const urdf::Color& c = visual.material->color;
      part.color = Eigen::Vector3d(c.r, c.g, c.b);
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
        const std::filesystem::path path = find_mesh_(mesh.filename);
        if (path.empty()) {
          scene->warnings.push_back(source_ + ": link '" + link.name + "': mesh '" + mesh.filename +
                                    "' is not in the model's files; drawn as a box of the "
                                    "link's inertia (submit the model with its meshes)");
          scene->visuals.push_back(Placeholder(link, frame, mesh.filename));
          return;
        }
        part.geometry = MeshFile{path, !urdf_colour};
        part.mesh_filename = mesh.filename;
        part.scale = Eigen::Vector3d(mesh.scale.x, mesh.scale.y, mesh.scale.z);
        part.fallback = std::make_shared<const VisualPart>(Placeholder(link, frame, mesh.filename));
        break;
      }
      default:
        return;
    }
    scene->visuals.push_back(std::move(part));
  }

  std::string source_;
  MeshFinder find_mesh_;
  bool floating_base_ = false;
  std::string scene_root_;  // the URDF's root link
  const model_files::UrdfOutline* outline_ = nullptr;
  std::map<std::string, int> frame_of_link_;
};

}  // namespace

SceneDescription SceneFromUrdf(const std::string& text, const std::string& source,
                               const std::filesystem::path& asset_directory) {
  return SceneFromUrdf(text, source, BundleMeshFinder(asset_directory));
}

SceneDescription SceneFromUrdf(const std::string& text, const std::string& source,
                               const MeshFinder& find_mesh, bool floating_base) {
  return UrdfSceneBuilder(source, find_mesh, floating_base).Build(text);
}

SceneDescription SceneFromUrdfFile(const std::filesystem::path& path,
                                   const std::vector<std::string>& package_path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code error;
  if (!in || !std::filesystem::is_regular_file(path, error)) {
    throw InputError(path.string() + ": cannot read the URDF file; check the path");
  }
  std::ostringstream text;
  text << in.rdbuf();
  return SceneFromUrdf(text.str(), path.string(), DiskMeshFinder(path.parent_path(), package_path));
}

}  // namespace mbstream::viewer
