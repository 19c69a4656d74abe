#include "viewer/model/sdf_scene.h"

#include <map>

#include <sdf/Joint.hh>

#include "common/check.h"
#include "urdf_reading/sdf_reading.h"
#include "viewer/model/shape_mesh.h"

namespace mbstream::viewer {

namespace {

namespace ur = urdf_reading;

constexpr int kResolution = 32;
constexpr double kPlaceholderEdge = 0.05;  // m

ChainJointKind KindOf(const sdf::Joint& joint) {
  switch (joint.Type()) {
    case sdf::JointType::PRISMATIC:
      return ChainJointKind::kPrismatic;
    case sdf::JointType::FIXED:
      return ChainJointKind::kFixed;
    default:  // revolute, continuous; ball: three revolutes (SceneFromSdf)
      return ChainJointKind::kRevolute;
  }
}

bool IsTcpName(std::string name) {
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return name == "tcp" || name == "tool0";
}

// The part that draws `visual` in link frame `frame` (placed at X_LV in it).
VisualPart PartOf(const ur::SdfVisual& visual, int frame, const Eigen::Isometry3d& X_LV,
                  const MeshFinder& find_mesh, std::vector<std::string>* warnings) {
  VisualPart part;
  part.name = visual.link;
  part.frame = frame;
  part.placement = X_LV;
  const std::optional<Eigen::Vector3d> colour = visual.diffuse ? visual.diffuse : visual.ambient;
  if (colour) part.color = *colour;
  if (const auto* box = std::get_if<ur::SdfBox>(&visual.geometry)) {
    part.geometry = CubeMesh({box->size});
    part.placement = part.placement * Eigen::Translation3d(-box->size / 2);
  } else if (const auto* cylinder = std::get_if<ur::SdfCylinder>(&visual.geometry)) {
    part.geometry = CylinderMesh({2 * cylinder->radius, kResolution, cylinder->length});
    part.placement = part.placement * Eigen::Translation3d(0, 0, -cylinder->length / 2);
  } else if (const auto* sphere = std::get_if<ur::SdfSphere>(&visual.geometry)) {
    part.geometry = SphereMesh({sphere->radius, kResolution});
  } else {
    const auto& mesh = std::get<ur::SdfMesh>(visual.geometry);
    part.mesh_filename = mesh.uri;
    VisualPart placeholder = part;
    const Eigen::Vector3d edge = Eigen::Vector3d::Constant(kPlaceholderEdge);
    placeholder.geometry = CubeMesh({edge});
    placeholder.placement = X_LV * Eigen::Translation3d(-edge / 2);
    placeholder.color = kPlaceholderColour;
    placeholder.opacity = kPlaceholderOpacity;
    placeholder.placeholder = true;
    const std::filesystem::path path = find_mesh(mesh.uri);
    if (path.empty()) {
      warnings->push_back(visual.where + ": link '" + visual.link + "': mesh '" + mesh.uri +
                          "' is not found; drawn as a placeholder cube (give --package-path "
                          "DIR, or submit the model with its meshes)");
      return placeholder;
    }
    part.geometry = MeshFile{path, !colour};
    part.scale = mesh.scale;
    part.fallback = std::make_shared<const VisualPart>(std::move(placeholder));
  }
  return part;
}

}  // namespace

SceneDescription SceneFromSdf(const std::string& text, const std::string& source,
                              const MeshFinder& find_mesh) {
  const ur::SdfFile file(text, source);
  const ur::SdfTree tree = ur::ChooseSdfTree(file);
  const std::vector<ur::SdfLinkFrame> frames = ur::SdfLinkFrames(file, tree);

  SceneDescription scene;
  scene.title = file.model().Name();
  scene.joints_named_as_model = true;
  std::map<std::string, int> frame_of{{ur::kSdfWorld, 0}};
  std::map<std::string, Eigen::Isometry3d> X_ML{{ur::kSdfWorld, Eigen::Isometry3d::Identity()}};
  scene.frame_names.push_back(ur::kSdfWorld);
  std::vector<ChainJoint> joints;
  for (size_t k = 0; k < tree.tree.size(); ++k) {
    const ur::SdfJointOutline& outline = tree.joints[tree.tree[k]];
    const ur::SdfLinkFrame& frame = frames[k];
    ChainJoint joint;
    joint.name = outline.joint->Name();
    joint.parent = frame_of.at(outline.parent);
    joint.pre = X_ML.at(outline.parent).inverse() * frame.X_ML;
    joint.kind = KindOf(*outline.joint);
    if (outline.joint->Type() == sdf::JointType::BALL) {
      // Three revolute joints through the centre, as the server's model (SdfBallAxisName).
      for (int axis = 0; axis < 2; ++axis) {
        ChainJoint inner = joint;
        inner.name = ur::SdfBallAxisName(outline.joint->Name(), axis);
        inner.axis = Eigen::Vector3d::Unit(axis);
        joints.push_back(std::move(inner));
        scene.frame_names.push_back(joints.back().name);
        joint.parent = static_cast<int>(joints.size());
        joint.pre = Eigen::Isometry3d::Identity();
      }
      joint.name = ur::SdfBallAxisName(outline.joint->Name(), 2);
      joint.axis = Eigen::Vector3d::UnitZ();
    }
    if (joint.kind != ChainJointKind::kFixed && outline.joint->Type() != sdf::JointType::BALL) {
      joint.axis = ur::SdfJointAxis(file, outline, frame.X_ML);
    }
    joints.push_back(std::move(joint));
    frame_of[frame.link] = static_cast<int>(joints.size());
    X_ML[frame.link] = frame.X_ML;
    scene.frame_names.push_back(frame.link);
  }
  scene.chain = KinematicChain(Eigen::Isometry3d::Identity(), std::move(joints));
  scene.initial_q.assign(scene.chain.dof(), 0.0);

  for (const ur::SdfVisual& visual : ur::SdfVisuals(file, &scene.warnings)) {
    const Eigen::Isometry3d X_LV = X_ML.at(visual.link).inverse() * visual.X_MV;
    scene.visuals.push_back(
        PartOf(visual, frame_of.at(visual.link), X_LV, find_mesh, &scene.warnings));
  }
  for (const std::string& name : scene.frame_names) {
    if (!IsTcpName(name)) continue;
    ProbePoint probe;
    probe.name = "tcp";
    probe.frame = frame_of.at(name);
    probe.refer = 0;
    probe.refer_name = ur::kSdfWorld;
    scene.probes.push_back(probe);
    break;
  }
  return scene;
}

}  // namespace mbstream::viewer
